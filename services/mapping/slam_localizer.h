#pragma once
// Localisation from the mapping run's SLAM: the pose graph's pose of the newest scan integrated,
// carried to now by odometry. navd localises this way while it builds the map it stands on
// (exploration): the served map is then the one being built, so matching scans against it would
// only agree with itself. Without a SLAM run's pose newer than the last SetPose it dead-reckons
// from that anchor. Map frame, metres, radians.
#include <mutex>

#include "services/localization/odometry_history.h"
#include "services/localization/odometry_localizer.h"
#include "services/mapping/map_builder.h"

namespace navd::mapping {

class SlamLocalizer : public localization::Localizer {
 public:
  explicit SlamLocalizer(const MapBuilder& builder) : builder_(builder) {}
  std::string name() const override { return "slam"; }
  void AddOdometry(const localization::OdometryReading& reading) override;
  localization::PoseEstimate Estimate() const override;
  // Only while a SLAM run is active; scan matching against its own map is cheap and precise, but
  // a pose graph without closures drifts (fault tolerance 3).
  localization::MethodContext Suitability(bool laser_fresh) const override;

 private:
  void ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) override;

  const MapBuilder& builder_;
  localization::OdometryLocalizer dead_reckoning_;
  mutable std::mutex mutex_;
  // Long enough to reach back past the scan the SLAM worker integrated last (10 s at 50 Hz).
  localization::OdometryHistory odometry_{512};
  double anchored_at_ = -1e18;  // odometry stamp of the last SetPose
};

}  // namespace navd::mapping
