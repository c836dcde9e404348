#pragma once
// Nav2's voxel layer: what sensors saw in 3-D that the map lacks, kept per map cell as a column of
// height slices (one bit each, as Nav2's voxel grid packs them). A point marks its slice; a ray
// from the sensor to a point clears every slice it passes through before it, so a box moved away
// is cleared by the first look at the floor where it stood, while a table top over a cell the rays
// pass beneath stays marked. A column with a slice marked is an obstacle. Marks not seen again for
// `decay` seconds are forgotten (out of the camera's narrow view nothing clears them).
// Map frame, metres, seconds.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "services/common/occupancy_grid.h"

namespace navd::perception {

struct VoxelObstacleLayerOptions {
  double slice = 0.1;   // m per height slice, from the floor up
  int slices = 16;      // the column's height: slices * slice (1.6 m by default)
  double decay = 20.0;  // s a mark lasts without being seen again
};

class VoxelObstacleLayer {
 public:
  // Covers the cells of `geometry` (its size, resolution and origin; its cells are not read).
  VoxelObstacleLayer(const OccupancyGrid& geometry, const VoxelObstacleLayerOptions& options = {});

  // One observation at time `now` from a sensor at `sensor`: rays to every point in `hits` and in
  // `free_ends` clear what they pass; then `hits` are marked. Points off the layer are skipped.
  void Update(const Eigen::Vector3d& sensor, const std::vector<Eigen::Vector3d>& hits,
              const std::vector<Eigen::Vector3d>& free_ends, double now);
  // Forgets marks older than `decay` at `now`.
  void Decay(double now);
  bool IsObstacle(const CellIndex& c) const { return columns_[Flat(c)] != 0; }
  // The centres of the cells with a mark (map frame).
  std::vector<Point2> Obstacles() const;
  size_t obstacle_count() const;
  const OccupancyGrid& geometry() const { return geometry_; }
  // Bumped by every change of the marks, so readers can tell a new layer from the last one.
  uint64_t version() const { return version_; }

 private:
  size_t Flat(const CellIndex& c) const { return static_cast<size_t>(c.y) * geometry_.width() + c.x; }
  // The slices between heights z0 and z1 (either order), as a bit mask.
  uint32_t SliceMask(double z0, double z1) const;
  void ClearRay(const Eigen::Vector3d& from, const Eigen::Vector3d& to);

  OccupancyGrid geometry_;
  VoxelObstacleLayerOptions o_;
  std::vector<uint32_t> columns_;  // bit k: slice k is marked
  std::vector<float> marked_at_;   // s, when the column was last marked
  uint64_t version_ = 0;
};

}  // namespace navd::perception
