#pragma once
// How much of a world a built map shows, judged against the world's true map: of the free cells
// the robot could reach from its start (4-connected through true free space), the share the
// built map knows at all, and the share it knows as free. Exploration's measure of "complete".
// The built map may have any origin and resolution; both are in the same (map) frame, metres.
#include "services/common/occupancy_grid.h"

namespace navd::mapping {

struct MapCoverage {
  size_t reachable_cells = 0;  // of the truth
  double known = 0.0;          // 0..1 of them mapped (free or occupied)
  double known_free = 0.0;     // 0..1 of them mapped free (below free_below)
};

MapCoverage CoverageOf(const OccupancyGrid& built, const OccupancyGrid& truth, const Point2& start,
                       int free_below = 25);

}  // namespace navd::mapping
