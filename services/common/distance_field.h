#pragma once
// The obstacle distance transform: for every cell, the Euclidean distance (metres, centre to
// centre) to the nearest occupied cell. Exact, in linear time (Felzenszwalb and Huttenlocher,
// "Distance Transforms of Sampled Functions", 2012). Grid planners use it for obstacle discomfort
// and cost decay, localisers for likelihood fields.
#include <vector>

#include "services/common/occupancy_grid.h"

namespace navd {

class DistanceField {
 public:
  // `unknown_is_obstacle`: whether unknown cells (-1) count as obstacles.
  explicit DistanceField(const OccupancyGrid& grid, bool unknown_is_obstacle = false);

  // Metres to the nearest obstacle cell; infinity when the grid has none.
  double at(const CellIndex& c) const { return distance_[static_cast<size_t>(c.y) * width_ + c.x]; }
  const std::vector<double>& values() const { return distance_; }

 private:
  int width_;
  std::vector<double> distance_;
};

}  // namespace navd
