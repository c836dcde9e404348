#include "services/mapping/slam_localizer.h"

#include <optional>

namespace navd::mapping {

void SlamLocalizer::AddOdometry(const localization::OdometryReading& reading) {
  dead_reckoning_.AddOdometry(reading);
  std::lock_guard<std::mutex> lock(mutex_);
  odometry_.Add(reading);
}

void SlamLocalizer::ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  dead_reckoning_.SetPose(pose, covariance);
  std::lock_guard<std::mutex> lock(mutex_);
  anchored_at_ = odometry_.empty() ? -1e18 : odometry_.latest().stamp;
}

localization::PoseEstimate SlamLocalizer::Estimate() const {
  localization::PoseEstimate e = dead_reckoning_.Estimate();
  const auto session = builder_.session();
  if (!e.valid || !session) return e;
  const MappingStatus s = session->status();
  std::lock_guard<std::mutex> lock(mutex_);
  if (s.mode != MappingMode::kSlam || s.scans == 0 || s.stamp < anchored_at_ || odometry_.empty()) return e;
  // The scan's graph pose, moved by the odometry since that scan.
  const Pose2 odom_then = odometry_.At(s.stamp);
  e.pose = s.pose * (odom_then.inverse() * odometry_.latest().pose);
  // Scan matching against the run's own map holds a few centimetres between closures.
  e.covariance = Eigen::Vector3d(0.03 * 0.03, 0.03 * 0.03, 0.01 * 0.01).asDiagonal();
  e.quality = 1.0;
  return e;
}

localization::MethodContext SlamLocalizer::Suitability(bool laser_fresh) const {
  const auto session = builder_.session();
  const std::optional<MappingStatus> s = session ? std::optional<MappingStatus>(session->status()) : std::nullopt;
  const bool slam = s && s->active && s->mode == MappingMode::kSlam;  // one status: one consistent read
  return {name(), slam && laser_fresh ? 1.0 : 0.0, {4.0, 3.0, 4.0}};
}

}  // namespace navd::mapping
