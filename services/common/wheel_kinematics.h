#pragma once
// Wheel kinematics of book chapter 1 for the robot's drive: rim speeds from a body twist (Eq. 8 for
// a differential drive's two wheels, Eq. 12 for the three-wheel omnidirectional base, in the robot
// frame) and the body twist from rim speeds (the least-squares inverse, exact for consistent
// wheels). The same for travels: rim travel in metres <-> body-frame motion. Body frame x forward,
// y left; metres, radians.
#include <Eigen/Core>

#include "services/common/world.h"

namespace navd {

class WheelKinematics {
 public:
  explicit WheelKinematics(const RobotDescription& robot);
  int wheels() const { return wheels_; }
  // Rim speeds (or travels) of each wheel for (vx, vy, omega); unused rows are zero. Fixed 3-wheel
  // storage: fixed sizes keep these Eigen instantiations distinct from the dynamic-size ones in
  // libompl.
  Eigen::Vector3d WheelsOf(const Eigen::Vector3d& twist) const { return jacobian_ * twist; }
  // (vx, vy, omega) for rim speeds (or travels); a differential drive's vy is 0.
  Eigen::Vector3d TwistOf(const Eigen::Vector3d& wheels) const { return inverse_ * wheels; }
  // The body-frame covariance of a motion from independent per-wheel travel variances.
  Eigen::Matrix3d TwistCovariance(const Eigen::Vector3d& wheel_variances) const {
    return inverse_ * wheel_variances.asDiagonal() * inverse_.transpose();
  }

 private:
  int wheels_ = 2;
  Eigen::Matrix3d jacobian_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d inverse_ = Eigen::Matrix3d::Zero();
};

}  // namespace navd
