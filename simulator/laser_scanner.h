#pragma once
// A planar laser range finder (default: Hokuyo URG-04LX): rays cast through the occupancy grid
// cell by cell (Amanatides-Woo traversal), Gaussian range noise, max-range readings reported as
// range_max + 1 so consumers can tell "no return". Angles in the robot frame, counter-clockwise.
#include <random>
#include <vector>

#include "services/common/occupancy_grid.h"
#include "services/common/world.h"

namespace navd::sim {

class LaserScanner {
 public:
  explicit LaserScanner(const LaserDescription& description) : d_(description) {}
  // Ranges for a scanner at `pose` (map frame), beam i at angle angle_min() + i * increment().
  std::vector<float> Scan(const Pose2& pose, const OccupancyGrid& map, std::mt19937_64& rng) const;
  double angle_min() const { return -d_.fov / 2; }
  double angle_max() const { return d_.fov / 2; }
  double increment() const { return d_.beams > 1 ? d_.fov / (d_.beams - 1) : 0.0; }
  const LaserDescription& description() const { return d_; }

  // Distance from `origin` along `angle` (map frame) to the first occupied cell, or max_range.
  static double CastRay(const OccupancyGrid& map, const Point2& origin, double angle, double max_range);

 private:
  LaserDescription d_;
};

}  // namespace navd::sim
