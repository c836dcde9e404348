#include "simulator/diff_drive_robot.h"

#include <algorithm>
#include <cmath>

namespace navd::sim {

DiffDriveRobot::DiffDriveRobot(const RobotDescription& description, const Pose2& start, std::mt19937_64& rng)
    : d_(description), rng_(rng), pose_(start) {}

void DiffDriveRobot::Command(const Twist2& twist) {
  target_ = ClampWheels(ToWheels(twist, d_.wheel_base), d_.max_wheel_speed);
}

bool DiffDriveRobot::Step(double dt, const OccupancyGrid& map) {
  // Wheels approach their targets within the acceleration limit; each achieves its speed with
  // multiplicative noise (motor and floor variation).
  std::normal_distribution<double> unit(0.0, 1.0);
  auto approach = [&](double current, double target) {
    const double step = d_.max_wheel_accel * dt;
    return current + std::clamp(target - current, -step, step);
  };
  wheels_.left = approach(wheels_.left, target_.left);
  wheels_.right = approach(wheels_.right, target_.right);
  const double left = wheels_.left * (1.0 + d_.actuator_noise * unit(rng_));
  const double right = wheels_.right * (1.0 + d_.actuator_noise * unit(rng_));

  const Pose2 next = IntegrateDiffDrive(pose_, left * dt, right * dt, d_.wheel_base);
  const bool blocked = map.DiscHitsObstacle(next.translation(), d_.radius);
  double d_left = left * dt, d_right = right * dt;
  if (blocked) {
    // The robot stays where it is; its wheels stall.
    wheels_ = {};
    d_left = d_right = 0.0;
    if (!in_collision_) ++collisions_;
  } else {
    distance_ += Distance(pose_.translation(), next.translation());
    pose_ = next;
  }
  in_collision_ = blocked;

  // Encoders count whole ticks of the true wheel rotation, which slips a little against the floor.
  const double metres_per_tick = 2.0 * M_PI * d_.wheel_radius / d_.encoder_ticks_per_rev;
  ticks_left_ += d_left * (1.0 + d_.encoder_noise * unit(rng_)) / metres_per_tick;
  ticks_right_ += d_right * (1.0 + d_.encoder_noise * unit(rng_)) / metres_per_tick;
  const long long new_left = static_cast<long long>(std::floor(ticks_left_));
  const long long new_right = static_cast<long long>(std::floor(ticks_right_));
  const double m_left = (new_left - counted_left_) * metres_per_tick;
  const double m_right = (new_right - counted_right_) * metres_per_tick;
  counted_left_ = new_left;
  counted_right_ = new_right;

  odom_pose_ = IntegrateDiffDrive(odom_pose_, m_left, m_right, d_.wheel_base);
  odom_twist_ = ToTwist({m_left / dt, m_right / dt}, d_.wheel_base);
  // Odometry uncertainty grows with wheel travel (independent slip on each wheel).
  const double var_l = std::pow(d_.encoder_noise * m_left, 2) + std::pow(metres_per_tick, 2) / 12.0 * (m_left != 0);
  const double var_r = std::pow(d_.encoder_noise * m_right, 2) + std::pow(metres_per_tick, 2) / 12.0 * (m_right != 0);
  const double c = std::cos(odom_pose_.theta), s = std::sin(odom_pose_.theta);
  const double var_s = (var_l + var_r) / 4.0;
  odom_cov_(0, 0) += var_s * c * c;
  odom_cov_(1, 1) += var_s * s * s;
  odom_cov_(0, 1) += var_s * c * s;
  odom_cov_(1, 0) = odom_cov_(0, 1);
  odom_cov_(2, 2) += (var_l + var_r) / (d_.wheel_base * d_.wheel_base);
  return blocked;
}

}  // namespace navd::sim
