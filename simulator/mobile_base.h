#pragma once
// A simulated wheeled base (differential drive, three-wheel omnidirectional, or a unicycle driven
// by accelerations): commanded motion, wheel dynamics with speed and acceleration limits, actuator
// noise, wheel slip, quantised wheel encoders and the odometry a robot's firmware would compute
// from them. Collisions are the Simulation's business: it proposes a motion, the world accepts or
// refuses it. World frame = map frame; metres, radians, seconds; body frame x forward, y left.
#include <Eigen/Core>
#include <random>
#include <vector>

#include "services/common/pose2.h"
#include "services/common/wheel_kinematics.h"
#include "services/common/world.h"

namespace navd::sim {

// A body twist: forward, leftward (omni only) and angular velocity.
struct BodyTwist {
  double vx = 0.0;     // m/s
  double vy = 0.0;     // m/s
  double omega = 0.0;  // rad/s
};

class MobileBase {
 public:
  MobileBase(const RobotDescription& description, const Pose2& start, uint64_t seed);

  // Velocity command (cmd_vel). Non-holonomic drives ignore vy. Clamped to the drive's limits.
  void CommandVelocity(const BodyTwist& twist);
  // Acceleration inputs u1 (m/s^2) and u2 (rad/s^2) of the chapter-7 unicycle, clamped to its
  // limits; held until the next command. Other drives turn them into velocity targets too.
  void CommandAcceleration(double linear, double angular);
  void Stop() { CommandVelocity({}); }

  // The true pose after dt if nothing is in the way (the wheels' dynamics advance now).
  Pose2 ProposeMotion(double dt);
  // Ends the step: moved to the proposed pose, or blocked (the wheels stall, the robot stays).
  // Encoders and odometry see the wheels' travel either way.
  void CommitMotion(bool blocked, double dt);

  const Pose2& true_pose() const { return pose_; }
  BodyTwist true_twist() const { return twist_; }
  const Pose2& odom_pose() const { return odom_pose_; }
  BodyTwist odom_twist() const { return odom_twist_; }
  const Eigen::Matrix3d& odom_covariance() const { return odom_cov_; }
  // Whole encoder ticks counted per wheel, and the wheel angles they stand for (radians).
  const std::vector<long long>& encoder_ticks() const { return counted_; }
  std::vector<double> wheel_angles() const;
  std::vector<double> wheel_speeds() const { return std::vector<double>(wheels_.data(), wheels_.data() + wheels_n_); }
  double distance_travelled() const { return distance_; }
  const RobotDescription& description() const { return d_; }
  int wheel_count() const { return wheels_n_; }

 private:
  // Rim speeds for a body twist and its least-squares inverse (book ch. 1 Eqs. 8 and 12).
  Eigen::Vector3d WheelsOf(const BodyTwist& t) const;
  BodyTwist TwistOf(const Eigen::Vector3d& wheels) const;
  void ClampToLimits(Eigen::Vector3d& wheels) const;

  RobotDescription d_;
  WheelKinematics kinematics_;
  std::mt19937_64 rng_;
  int wheels_n_ = 2;
  Pose2 pose_;
  Pose2 proposed_;
  BodyTwist twist_;                                   // achieved this step
  Eigen::Vector3d target_ = Eigen::Vector3d::Zero();  // rim speeds the motors aim for
  Eigen::Vector3d wheels_ = Eigen::Vector3d::Zero();  // rim speeds reached
  Eigen::Vector3d travel_ = Eigen::Vector3d::Zero();  // rim travel this step (m), before slip
  // Unicycle state (chapter 7, Eq. 9: v and theta-dot) and its held acceleration inputs.
  double v_ = 0.0, omega_ = 0.0;
  double u1_ = 0.0, u2_ = 0.0;
  bool accel_mode_ = false;
  BodyTwist velocity_target_;
  std::vector<double> ticks_;       // true wheel rotation in (fractional) ticks
  std::vector<long long> counted_;  // whole ticks seen by the encoders
  Pose2 odom_pose_;
  BodyTwist odom_twist_;
  Eigen::Matrix3d odom_cov_ = Eigen::Matrix3d::Zero();
  double distance_ = 0.0;
};

}  // namespace navd::sim
