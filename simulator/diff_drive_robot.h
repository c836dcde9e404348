#pragma once
// The simulated differential-drive robot: true pose, wheel dynamics (speed and acceleration
// limits, actuator noise), wheel encoders (quantised ticks with slip noise), odometry computed from
// those ticks as a robot's firmware would, and collisions (a disc that never enters an occupied
// cell). World frame = map frame; metres, radians, seconds.
#include <Eigen/Core>
#include <random>

#include "services/common/diff_drive.h"
#include "services/common/occupancy_grid.h"
#include "services/common/world.h"

namespace navd::sim {

class DiffDriveRobot {
 public:
  DiffDriveRobot(const RobotDescription& description, const Pose2& start, std::mt19937_64& rng);

  // Commanded body twist; converted to wheel speeds and clamped to the wheel limits.
  void Command(const Twist2& twist);
  // Advances by dt seconds against `map`. Returns true when the robot was blocked by an obstacle.
  bool Step(double dt, const OccupancyGrid& map);

  const Pose2& true_pose() const { return pose_; }
  const Pose2& odom_pose() const { return odom_pose_; }
  const Eigen::Matrix3d& odom_covariance() const { return odom_cov_; }
  Twist2 true_twist() const { return ToTwist(wheels_, d_.wheel_base); }
  Twist2 odom_twist() const { return odom_twist_; }
  bool in_collision() const { return in_collision_; }
  uint32_t collisions() const { return collisions_; }
  double distance_travelled() const { return distance_; }
  const RobotDescription& description() const { return d_; }

 private:
  RobotDescription d_;
  std::mt19937_64& rng_;
  Pose2 pose_;
  WheelSpeeds target_;
  WheelSpeeds wheels_;              // achieved rim speeds
  double ticks_left_ = 0.0;         // true wheel rotation in ticks (fractional)
  double ticks_right_ = 0.0;
  long long counted_left_ = 0;      // whole ticks seen by the encoders
  long long counted_right_ = 0;
  Pose2 odom_pose_;
  Twist2 odom_twist_;
  Eigen::Matrix3d odom_cov_ = Eigen::Matrix3d::Zero();
  bool in_collision_ = false;
  uint32_t collisions_ = 0;
  double distance_ = 0.0;
};

}  // namespace navd::sim
