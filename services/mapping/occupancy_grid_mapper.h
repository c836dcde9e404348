#pragma once
// Occupancy grid mapping with known poses (seed 002 section 2.2, Bayesian log-odds): each laser
// beam lowers the log-odds of the cells it crosses (free) and raises the cell it ends in
// (occupied); beams at maximum range only clear. The grid grows to fit the data. Map frame,
// metres, radians.
#include <vector>

#include "services/common/occupancy_grid.h"
#include "services/common/pose2.h"

namespace navd::mapping {

struct MapperOptions {
  double resolution = 0.05;    // m
  double l_occupied = 0.85;    // log-odds added at a hit
  double l_free = -0.4;        // log-odds added along a beam
  double l_min = -4.0, l_max = 4.0;  // clamps keep the map responsive to change
  double max_range = 50.0;     // m: longer readings are no-returns
  double usable_range = 15.0;  // m: beams are cut here (long beams are mostly noise)
};

class OccupancyGridMapper {
 public:
  // `min`/`max`: the map-frame extent to cover (e.g. the poses' bounding box plus the range).
  OccupancyGridMapper(const Point2& min, const Point2& max, const MapperOptions& options = {});
  // Integrates a scan taken from `laser_pose`; beam i at angle_min + i * increment.
  void AddScan(const Pose2& laser_pose, const std::vector<float>& ranges, double angle_min, double increment);
  // Probabilities as map cells: 0..100, -1 where no beam ever reached.
  OccupancyGrid ToGrid() const;

 private:
  OccupancyGrid geometry_;       // size, origin and resolution only
  MapperOptions o_;
  std::vector<float> log_odds_;
  std::vector<uint8_t> seen_;
};

}  // namespace navd::mapping
