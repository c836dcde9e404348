#include "services/localization/wheel_odometry.h"

#include <cmath>

#include "services/common/diff_drive.h"

namespace navd::localization {

WheelOdometry::WheelOdometry(const RobotDescription& robot) : robot_(robot), kinematics_(robot) {}

std::optional<OdometryReading> WheelOdometry::AddWheelAngles(const std::vector<double>& angles, double stamp) {
  if (static_cast<int>(angles.size()) != kinematics_.wheels()) return std::nullopt;
  for (double a : angles) {
    if (!std::isfinite(a)) return std::nullopt;
  }
  if (!started_) {
    started_ = true;
    last_ = angles;
    odometry_.stamp = stamp;
    return odometry_;
  }
  const double tick = 2.0 * M_PI * robot_.wheel_radius / std::max(1, robot_.encoder_ticks_per_rev);
  Eigen::Vector3d travel = Eigen::Vector3d::Zero(), variance = Eigen::Vector3d::Zero();
  for (int i = 0; i < kinematics_.wheels(); ++i) {
    travel[i] = (angles[i] - last_[i]) * robot_.wheel_radius;
    // Slip in proportion to the travel, plus the encoder's quantisation (uniform over a tick).
    variance[i] = std::pow(robot_.encoder_noise * travel[i], 2) + (travel[i] != 0.0 ? tick * tick / 12.0 : 0.0);
  }
  last_ = angles;
  const Eigen::Vector3d step = kinematics_.TwistOf(travel);
  odometry_.pose = IntegrateTwist(odometry_.pose, step.x(), step.y(), step.z());
  Eigen::Matrix3d rot = Eigen::Matrix3d::Identity();
  const double c = std::cos(odometry_.pose.theta), s = std::sin(odometry_.pose.theta);
  rot.topLeftCorner<2, 2>() << c, -s, s, c;
  odometry_.covariance += rot * kinematics_.TwistCovariance(variance) * rot.transpose();
  odometry_.stamp = stamp;
  return odometry_;
}

}  // namespace navd::localization
