#pragma once
// Ray casting against a static occupancy grid, accelerated by its obstacle distance field: far
// from walls a ray leaps ahead by the clearance (no obstacle can lie closer), near them it walks
// cell by cell with the exact traversal, so it returns the same hit as a pure cell walk at a
// fraction of the cost. Cells outside the grid count as walls. Metres, radians, map frame.
#include <vector>

#include "services/common/distance_field.h"
#include "services/common/occupancy_grid.h"

namespace navd::sim {

// A disc in the world that sensors see and robots bump into (a robot, a person, a moving obstacle).
struct Disc {
  Point2 centre;
  double radius = 0.0;
  int id = -1;  // who it is (Simulation's body index), so a sensor can skip its own robot
};

class RayCaster {
 public:
  explicit RayCaster(OccupancyGrid grid);

  // Distance from `origin` along `angle` to the first occupied cell, or `max_range` when none.
  double Cast(const Point2& origin, double angle, double max_range) const;
  // True when a disc at p of `radius` overlaps an occupied cell or leaves the grid.
  bool DiscHitsWall(const Point2& p, double radius) const;
  // Metres from p's cell centre to the nearest occupied cell centre.
  double Clearance(const Point2& p) const;

  const OccupancyGrid& grid() const { return grid_; }

 private:
  OccupancyGrid grid_;
  std::vector<float> clearance_;  // distance field in cells, float to halve its cache footprint
};

// Distance along the unit direction `dir` from `origin` to where the ray enters `disc`, or
// infinity when it misses (or starts inside it).
double RayDiscDistance(const Point2& origin, const Point2& dir, const Disc& disc);

}  // namespace navd::sim
