#pragma once
// Odometry from wheel encoders (book chapter 1, Eqs. 7-12), as the robot's firmware would compute
// it: each wheel's angle increment times its radius is its rim travel, the drive's kinematics turn
// the travels into a body-frame motion, and that motion is integrated along its arc (the exact
// SE(2) exponential). The covariance grows with the travel (encoder quantisation and slip).
// navd uses it with `--odometry encoders`, reading sensor_msgs/JointState wheel angles. Odom
// frame; metres, radians, seconds.
#include <optional>
#include <vector>

#include "services/common/wheel_kinematics.h"
#include "services/localization/localizer.h"

namespace navd::localization {

class WheelOdometry {
 public:
  explicit WheelOdometry(const RobotDescription& robot);
  // Cumulative wheel angles (radians, one per wheel: left, right for a differential drive). The
  // first call anchors the odometry at the origin. Returns nothing for a wrong wheel count or
  // non-finite angles (never integrated).
  std::optional<OdometryReading> AddWheelAngles(const std::vector<double>& angles, double stamp);

 private:
  RobotDescription robot_;
  WheelKinematics kinematics_;
  bool started_ = false;
  std::vector<double> last_;
  OdometryReading odometry_;
};

}  // namespace navd::localization
