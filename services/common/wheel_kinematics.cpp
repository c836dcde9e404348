#include "services/common/wheel_kinematics.h"

#include <Eigen/Dense>
#include <cmath>

namespace navd {

WheelKinematics::WheelKinematics(const RobotDescription& robot) {
  if (robot.drive == DriveType::kOmni) {
    // Eq. 12 in the robot frame (theta = 0): v_i = -sin(a_i) vx + cos(a_i) vy + R omega.
    wheels_ = 3;
    for (int i = 0; i < 3; ++i) {
      const double a = robot.omni_wheel_angles[i];
      jacobian_.row(i) << -std::sin(a), std::cos(a), robot.omni_wheel_distance;
    }
  } else {
    // Eq. 8: left and right rims; a differential drive (or unicycle) cannot move sideways.
    wheels_ = 2;
    jacobian_.row(0) << 1.0, 0.0, -robot.wheel_base / 2.0;
    jacobian_.row(1) << 1.0, 0.0, robot.wheel_base / 2.0;
  }
  inverse_ = jacobian_.completeOrthogonalDecomposition().pseudoInverse();
}

}  // namespace navd
