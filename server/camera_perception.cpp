#include "server/camera_perception.h"

namespace navd::server {

CameraPerception::CameraPerception(DdsBridge& bridge, const MapStore& maps, const localization::Localizer& localizer,
                                   perception::DepthObstacleLayer& layer)
    : bridge_(bridge), maps_(maps), localizer_(localizer), layer_(layer) {
  bridge_.ReadCamera();
}

std::shared_ptr<const std::vector<Point2>> CameraPerception::Step(double now) {
  if (const auto map = maps_.Get(); map && map->version != map_version_) {
    map_version_ = map->version;
    layer_.SetMap(map->grid);
  }
  if (bridge_.cloud_count() != clouds_seen_) {
    clouds_seen_ = bridge_.cloud_count();
    const std::shared_ptr<const DdsBridge::CameraCloud> cloud = bridge_.LatestCloud();
    const localization::PoseEstimate estimate = localizer_.Estimate();
    const std::optional<Pose2> at_estimate = bridge_.OdometryAt(estimate.stamp);
    const std::optional<Pose2> at_cloud = cloud ? bridge_.OdometryAt(cloud->stamp) : std::nullopt;
    if (cloud && estimate.valid && at_estimate && at_cloud)
      layer_.AddCloud(cloud->points, estimate.pose * (at_estimate->inverse() * *at_cloud), now);
  }
  return layer_.Obstacles();
}

}  // namespace navd::server
