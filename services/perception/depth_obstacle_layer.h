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
  // For a robot `height` m tall: obstacles up to 5 cm over its top (what passes that close still
  // counts), in slices that cover them (thicker ones for a robot over 3 m).
  static DepthObstacleLayerOptions ForRobot(double height);
};

class DepthObstacleLayer {
 public:
  DepthObstacleLayer(const DepthCameraDescription& camera, const DepthObstacleLayerOptions& options);
  // The map to keep the layer over. What the map holds (within a cell of its walls) is not marked.
  // A map of another size, resolution or origin starts the marks afresh; the same grid grown or
  // corrected (a map being built) keeps them.
  void SetMap(const OccupancyGrid& map);
  // A cloud (the camera's optical frame) taken with the robot at `robot` (map frame) at `now`.
  // Ignored before a map is set.
  void AddCloud(const std::vector<Eigen::Vector3f>& points, const Pose2& robot, double now);
  // The marked cells' centres (map frame), as of the last cloud; empty before any.
  std::shared_ptr<const std::vector<Point2>> Obstacles() const;
  // Bumped by every change of the marked cells.
  uint64_t version() const;

 private:
  ObstacleCloudFilter filter_;
  DepthCameraDescription camera_;
  VoxelObstacleLayerOptions layer_options_;
  mutable std::mutex mutex_;
  std::optional<VoxelObstacleLayer> layer_;
  // The map's occupied cells grown by one cell: points there are walls the map holds.
  std::shared_ptr<const OccupancyGrid> known_;
  std::shared_ptr<const std::vector<Point2>> obstacles_ = std::make_shared<const std::vector<Point2>>();
  uint64_t version_ = 0;
  int stride_;  // pixels: the filter reads every stride-th row and column of the depth image
};

}  // namespace navd::perception
