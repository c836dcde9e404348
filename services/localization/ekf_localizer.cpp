#include "services/localization/ekf_localizer.h"

#include <Eigen/Dense>
#include <cmath>

#include "services/localization/scan_points.h"

namespace navd::localization {
namespace {
// Odometry is folded into the covariance in stretches of at most this much motion (and at every
// scan correction).
constexpr double kFoldDistance = 1.0;  // m
constexpr double kFoldAngle = 0.5;     // rad
}  // namespace

EkfLocalizer::EkfLocalizer(const OccupancyGrid& map, const EkfOptions& options, const Pose2& initial_pose,
                           const Eigen::Matrix3d& initial_covariance)
    : o_(options), model_(std::make_shared<const MapModel>(map, options)) {
  belief_.x << initial_pose.x, initial_pose.y, NormalizeAngle(initial_pose.theta);
  belief_.p = initial_covariance;
}

bool EkfLocalizer::SetMap(const OccupancyGrid& map) {
  auto model = std::make_shared<const MapModel>(map, o_);  // the costly part, outside the lock
  std::lock_guard<std::mutex> lock(mutex_);
  model_ = std::move(model);
  return true;
}

void EkfLocalizer::ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  std::lock_guard<std::mutex> lock(mutex_);
  belief_.x << pose.x, pose.y, pose.theta;
  belief_.p = covariance;
  corrected_at_odom_ = predicted_at_odom_ = latest_odom_;
  moved_since_correction_ = true;
  rejected_in_a_row_ = 0;
}

EkfLocalizer::Belief EkfLocalizer::Predicted(const Belief& b, const Pose2& d) const {
  // The odometry increment in the robot frame. Seed 002's eq. 2 moves dD along theta + dtheta/2,
  // which is where a differential drive's arc ends: the increment (dD cos(dtheta/2),
  // dD sin(dtheta/2), dtheta). Composing the measured increment instead is that model for a diff
  // drive and stays right for odometry whose reference point is not on the wheel axle (a laser's
  // pose swings sideways when the robot turns on the spot) or for an omnidirectional base.
  const double dist = std::hypot(d.x, d.y);
  const double c = std::cos(b.x.z()), s = std::sin(b.x.z());
  // Jacobians of x+ = x (+) d: A_x by the state, A_u by the increment (its rotation into the map).
  Eigen::Matrix3d a_x;
  a_x << 1, 0, -s * d.x - c * d.y, 0, 1, c * d.x - s * d.y, 0, 0, 1;
  Eigen::Matrix3d a_u;
  a_u << c, -s, 0, s, c, 0, 0, 0, 1;
  // U: along and across the motion k_distance per metre, heading k_turn per radian plus
  // k_turn_per_metre per metre; expressed on the increment's robot-frame axes.
  const double sd = o_.k_distance * dist;
  const double st = o_.k_turn * std::abs(d.theta) + o_.k_turn_per_metre * dist;
  Eigen::Matrix3d u = Eigen::Matrix3d::Zero();
  u.diagonal() << sd * sd, sd * sd, st * st;
  Eigen::Matrix3d q = Eigen::Matrix3d::Zero();
  q.diagonal() << o_.q_xy_per_metre * dist, o_.q_xy_per_metre * dist, o_.q_theta_per_metre * dist;
  Belief next;
  next.x = b.x + Eigen::Vector3d(c * d.x - s * d.y, s * d.x + c * d.y, d.theta);
  next.x.z() = NormalizeAngle(next.x.z());
  next.p = a_x * b.p * a_x.transpose() + a_u * u * a_u.transpose() + q;
  return next;
}

void EkfLocalizer::AddOdometry(const OdometryReading& reading) {
  if (!reading.pose.finite()) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!have_odom_) {
    latest_odom_ = corrected_at_odom_ = predicted_at_odom_ = reading.pose;
    have_odom_ = true;
  }
  latest_odom_ = reading.pose;
  // The covariance grows by each stretch of motion as one input, however many readings it came
  // in: U is per increment, so predicting at every reading would shrink the noise with the rate.
  const Pose2 pending = predicted_at_odom_.inverse() * latest_odom_;
  if (std::hypot(pending.x, pending.y) >= kFoldDistance || std::abs(pending.theta) >= kFoldAngle) {
    belief_ = Predicted(belief_, pending);
    predicted_at_odom_ = latest_odom_;
  }
  odom_history_.Add(reading);
  stamp_ = reading.stamp;
  const Pose2 since = corrected_at_odom_.inverse() * latest_odom_;
  if (std::hypot(since.x, since.y) >= o_.update_min_distance || std::abs(since.theta) >= o_.update_min_angle) {
    moved_since_correction_ = true;
  }
}

bool EkfLocalizer::AddScan(const ScanReading& scan) {
  if (!ScanHeaderIsUsable(scan)) return false;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!have_odom_ || !moved_since_correction_) return false;
  const std::vector<Point2> ends = ScanEndPoints(scan, o_.beams);
  // The match is made where the filter thinks the robot was when the scan was taken, and carried
  // to now with the odometry since.
  belief_ = Predicted(belief_, predicted_at_odom_.inverse() * latest_odom_);
  predicted_at_odom_ = latest_odom_;
  Eigen::Vector3d& x = belief_.x;
  Eigen::Matrix3d& p = belief_.p;
  const Pose2 now{x.x(), x.y(), x.z()};
  const Pose2 scan_from_now = odom_history_.At(scan.stamp).inverse() * latest_odom_;
  const ScanToMapFitResult fit = model_->fit.Fit(ends, now * scan_from_now.inverse());
  if (!fit.ok) {
    quality_ = 0.0;
    return false;
  }
  const Pose2 z = fit.pose * scan_from_now;
  Eigen::Vector3d innovation(z.x - x.x(), z.y - x.y(), NormalizeAngle(z.theta - x.z()));
  const Eigen::Matrix3d s = p + fit.covariance;
  const Eigen::Matrix3d s_inv = s.inverse();
  quality_ = (static_cast<double>(fit.inliers) / std::max(1, fit.points)) *
             std::exp(-0.5 * fit.rms * fit.rms / (o_.field.sigma_hit * o_.field.sigma_hit));
  if (!(innovation.dot(s_inv * innovation) <= o_.gate)) {
    if (++rejected_in_a_row_ < o_.reanchor_after) return false;
    x << z.x, z.y, z.theta;
    p = fit.covariance;
    rejected_in_a_row_ = 0;
    corrected_at_odom_ = latest_odom_;
    moved_since_correction_ = false;
    return true;
  }
  rejected_in_a_row_ = 0;
  // Joseph form: stays symmetric and positive definite with rounding.
  const Eigen::Matrix3d k = p * s_inv;
  const Eigen::Matrix3d i_k = Eigen::Matrix3d::Identity() - k;
  x += k * innovation;
  x.z() = NormalizeAngle(x.z());
  p = i_k * p * i_k.transpose() + k * fit.covariance * k.transpose();
  p = 0.5 * (p + p.transpose());
  corrected_at_odom_ = latest_odom_;
  moved_since_correction_ = false;
  return true;
}

PoseEstimate EkfLocalizer::Estimate() const {
  std::lock_guard<std::mutex> lock(mutex_);
  PoseEstimate e;
  e.valid = have_odom_;
  const Belief b = Predicted(belief_, predicted_at_odom_.inverse() * latest_odom_);
  e.pose = {b.x.x(), b.x.y(), b.x.z()};
  e.covariance = b.p;
  e.stamp = stamp_;
  e.quality = quality_;
  return e;
}

MethodContext EkfLocalizer::Suitability(bool laser_fresh) const {
  return {name(), laser_fresh ? 1.0 : 0.0, {4.0, 2.0, 1.0 + 4.0 * std::clamp(Estimate().quality, 0.0, 1.0)}};
}

int EkfLocalizer::rejected_in_a_row() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return rejected_in_a_row_;
}

}  // namespace navd::localization
