#pragma once
// Nav2's voxel layer for a depth camera: what it saw in 3-D that the map lacks, kept per map cell
// as a column of height slices (one bit each, as Nav2's voxel grid packs them). A point marks its
// slice. A marked slice inside the camera's view is cleared when the pixel through its centre saw
// as far as where that ray leaves it (a z-buffer test, instead of tracing a ray to every point:
// the marks in view are a few hundred, the points tens of thousands): a box moved away is cleared
// by the first look at the floor where it stood, while a table top stays marked as long as the
// pixels through it see it. Marks not seen again for
// `decay` seconds are forgotten (out of the camera's narrow view nothing clears them).
// Map frame, metres, seconds.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <vector>

#include "services/common/camera_frame.h"
#include "services/common/occupancy_grid.h"

namespace navd::perception {

struct VoxelObstacleLayerOptions {
  double slice = 0.1;   // m per height slice, from the floor up
  int slices = 16;      // the column's height: slices * slice (1.6 m by default)
  double decay = 20.0;  // s a mark lasts without being seen again
};

// What the camera saw, as a z-buffer: per pixel the nearest depth (m along the optical axis),
// infinity where it saw nothing; and where the camera was.
struct DepthView {
  PinholeIntrinsics intrinsics;
  int width = 0, height = 0;
  std::vector<float> depth;  // row-major, width * height
  Eigen::Isometry3d map_from_optical = Eigen::Isometry3d::Identity();
  double range_min = 0.0, range_max = 0.0;  // m: the camera's; beyond range_max a pixel saw nothing
  double noise = 0.0;  // the depth's standard deviation per m^2 of depth (DepthCameraDescription::noise)

  // The z-buffer of `points` (optical frame) for an image of `width` x `height`.
  static DepthView Of(const std::vector<Eigen::Vector3f>& points, const PinholeIntrinsics& intrinsics, int width,
                      int height);
  // The points of every stride-th row and column with a reading (optical frame): a decimated cloud.
  std::vector<Eigen::Vector3f> Points(int stride) const;
};

class VoxelObstacleLayer {
 public:
  // Covers the cells of `geometry` (its size, resolution and origin; its cells are not read).
  VoxelObstacleLayer(const OccupancyGrid& geometry, const VoxelObstacleLayerOptions& options = {});

  // One look at time `now`: marked slices in `view` that the camera saw past are cleared, then
  // `hits` (map frame) are marked. Points off the layer are skipped.
  void Update(const DepthView& view, const std::vector<Eigen::Vector3d>& hits, double now);
  // Forgets marks older than `decay` at `now`.
  void Decay(double now);
  bool IsObstacle(const CellIndex& c) const { return columns_[Flat(c)] != 0; }
  // The centres of the cells with a mark (map frame).
  std::vector<Point2> Obstacles() const;
  size_t obstacle_count() const { return marked_.size(); }
  const OccupancyGrid& geometry() const { return geometry_; }
  // Bumped by every change of the marks, so readers can tell a new layer from the last one.
  uint64_t version() const { return version_; }

 private:
  size_t Flat(const CellIndex& c) const { return static_cast<size_t>(c.y) * geometry_.width() + c.x; }
  // Drops the cells whose marks are all gone from marked_.
  void Compact();

  OccupancyGrid geometry_;
  VoxelObstacleLayerOptions o_;
  std::vector<uint32_t> columns_;  // bit k: slice k is marked
  std::vector<double> marked_at_;  // s, when the column was last marked (clock time: may be large)
  std::vector<size_t> marked_;     // the flat indices of the columns with a mark
  uint64_t version_ = 0;
};

}  // namespace navd::perception
