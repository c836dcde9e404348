#pragma once
// Dead reckoning: the map pose is the odometry pose carried through a fixed map<-odom transform,
// which SetPose re-anchors. Drift is not corrected; later localisers do that.
#include <mutex>

#include "services/localization/localizer.h"

namespace navd::localization {

class OdometryLocalizer : public Localizer {
 public:
  // initial_pose: where the robot stands in the map frame when odometry reads its first pose.
  explicit OdometryLocalizer(const Pose2& initial_pose = {});
  std::string name() const override { return "odometry"; }
  void AddOdometry(const OdometryReading& reading) override;
  PoseEstimate Estimate() const override;
  // Always works, costs nothing, never recovers from slip, and drifts.
  MethodContext Suitability(bool) const override { return {name(), 1.0, {5.0, 2.0, 2.0}}; }

 private:
  void ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) override;

  mutable std::mutex mutex_;
  Pose2 initial_pose_;
  Pose2 map_from_odom_;
  Eigen::Matrix3d anchor_covariance_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d odom_covariance_at_anchor_ = Eigen::Matrix3d::Zero();
  OdometryReading last_;
  bool have_reading_ = false;
};

}  // namespace navd::localization
