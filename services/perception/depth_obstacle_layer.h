#pragma once
// The depth camera's obstacle layer as navd keeps it: each cloud through ObstacleCloudFilter,
// placed in the map by the robot's pose at the cloud's stamp, into a VoxelObstacleLayer over the
// served map; the obstacles go to the plans and the guards as a snapshot. Thread-safe: clouds come
// in on the control thread, snapshots are read by planning and telemetry.
// Units: metres, seconds; map frame.
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "services/common/pose2.h"
#include "services/common/world.h"
#include "services/perception/obstacle_cloud_filter.h"
#include "services/perception/voxel_obstacle_layer.h"

namespace navd::perception {

struct DepthObstacleLayerOptions {
  ObstacleCloudFilterOptions filter;
  VoxelObstacleLayerOptions layer;
};

class DepthObstacleLayer {
 public:
  DepthObstacleLayer(const DepthCameraDescription& camera, const DepthObstacleLayerOptions& options);
  // A new map to keep the layer over: the marks start afresh. What the map holds (within a cell
  // of its walls) is not marked.
  void SetMap(const OccupancyGrid& map);
  // A cloud (the camera's optical frame) taken with the robot at `robot` (map frame) at `now`.
  // Ignored before a map is set.
  void AddCloud(const std::vector<Eigen::Vector3f>& points, const Pose2& robot, double now);
  // The marked cells' centres (map frame), as of the last cloud; empty before any.
  std::shared_ptr<const std::vector<Point2>> Obstacles() const;
  // The marked cells as a grid the size of the map (kOccupied where marked), and the layer's
  // version; nullopt before a map is set.
  std::optional<OccupancyGrid> Grid() const;
  uint64_t version() const;
  uint64_t clouds() const;

 private:
  ObstacleCloudFilter filter_;
  DepthCameraDescription camera_;
  VoxelObstacleLayerOptions layer_options_;
  mutable std::mutex mutex_;
  std::optional<VoxelObstacleLayer> layer_;
  // The map's occupied cells grown by one cell: points there are walls the map holds.
  std::shared_ptr<const OccupancyGrid> known_;
  std::shared_ptr<const std::vector<Point2>> obstacles_ = std::make_shared<const std::vector<Point2>>();
  uint64_t version_ = 0, clouds_ = 0;
  int stride_;  // pixels: the filter reads every stride-th row and column of the depth image
};

}  // namespace navd::perception
