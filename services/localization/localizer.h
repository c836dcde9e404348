#pragma once
// The interface of pose estimators: they consume odometry (and, later, scans) and report the
// robot's pose in the map frame with a covariance. Units: metres, radians, seconds.
#include <Eigen/Core>
#include <string>

#include "services/common/pose2.h"

namespace navd::localization {

// An odometry reading: the robot's pose in the odom frame (which drifts) and its covariance.
struct OdometryReading {
  Pose2 pose;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double stamp = 0.0;
};

struct PoseEstimate {
  Pose2 pose;                                             // map frame
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();   // (x, y, theta)
  double stamp = 0.0;
  bool valid = false;                                     // false until the first reading
};

class Localizer {
 public:
  virtual ~Localizer() = default;
  virtual std::string name() const = 0;
  virtual void AddOdometry(const OdometryReading& reading) = 0;
  // Re-anchors the estimate at `pose` (map frame) with `covariance` of (x, y, theta). Throws
  // navd::Error(kInvalidArgument) naming the field for non-finite values or a covariance that is
  // not symmetric with a non-negative diagonal.
  void SetPose(const Pose2& pose, const Eigen::Matrix3d& covariance);
  virtual PoseEstimate Estimate() const = 0;

 protected:
  // Called by SetPose with checked values; theta already in (-pi, pi].
  virtual void ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) = 0;
};

}  // namespace navd::localization
