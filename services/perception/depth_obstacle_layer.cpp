#include "services/perception/depth_obstacle_layer.h"

namespace navd::perception {

DepthObstacleLayer::DepthObstacleLayer(const DepthCameraDescription& camera, const DepthObstacleLayerOptions& options)
    : filter_(options.filter, camera), camera_(camera), layer_options_(options.layer) {}

void DepthObstacleLayer::SetMap(const OccupancyGrid& map) {
  std::lock_guard<std::mutex> lock(mutex_);
  layer_.emplace(map, layer_options_);
  obstacles_ = std::make_shared<const std::vector<Point2>>();
  ++version_;
}

void DepthObstacleLayer::AddCloud(const std::vector<Eigen::Vector3f>& points, const Pose2& robot, double now) {
  // The filter needs no lock: it reads only its options.
  const FilteredCloud seen = filter_.Filter(points);
  const double c = std::cos(robot.theta), s = std::sin(robot.theta);
  auto to_map = [&](const Eigen::Vector3f& p) {
    return Eigen::Vector3d(robot.x + c * p.x() - s * p.y(), robot.y + s * p.x() + c * p.y(), p.z());
  };
  std::vector<Eigen::Vector3d> hits, free_ends;
  hits.reserve(seen.obstacles.size());
  free_ends.reserve(seen.floor.size());
  for (const Eigen::Vector3f& p : seen.obstacles) hits.push_back(to_map(p));
  for (const Eigen::Vector3f& p : seen.floor) free_ends.push_back(to_map(p));
  const Eigen::Vector3d sensor = to_map(Eigen::Vector3f(
      static_cast<float>(camera_.mount_x), static_cast<float>(camera_.mount_y), static_cast<float>(camera_.mount_z)));
  std::lock_guard<std::mutex> lock(mutex_);
  if (!layer_) return;
  ++clouds_;
  const uint64_t before = layer_->version();
  layer_->Update(sensor, hits, free_ends, now);
  layer_->Decay(now);
  if (layer_->version() != before) {
    obstacles_ = std::make_shared<const std::vector<Point2>>(layer_->Obstacles());
    ++version_;
  }
}

std::shared_ptr<const std::vector<Point2>> DepthObstacleLayer::Obstacles() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return obstacles_;
}

std::optional<OccupancyGrid> DepthObstacleLayer::Grid() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!layer_) return std::nullopt;
  OccupancyGrid grid = layer_->geometry();
  for (const Point2& p : *obstacles_) grid.set(grid.CellOf(p), OccupancyGrid::kOccupied);
  return grid;
}

uint64_t DepthObstacleLayer::version() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return version_;
}

uint64_t DepthObstacleLayer::clouds() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return clouds_;
}

}  // namespace navd::perception
