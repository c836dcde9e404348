#pragma once
// A planning costmap: the occupancy grid with obstacles grown by the robot's radius plus a safety
// margin (Nav2's inflation layer, lethal part only). A cell is lethal when its centre lies within
// `inflation_radius` metres of an occupied cell's centre; unknown cells are lethal unless allowed.
#include <cstdint>
#include <memory>
#include <vector>

#include "services/common/occupancy_grid.h"

namespace navd::planning {

struct CostmapOptions {
  double inflation_radius = 0.30;  // metres: robot radius + margin
  bool unknown_is_lethal = true;
};

class Costmap {
 public:
  // Shares ownership of the grid, so a costmap outlives a map swap.
  Costmap(std::shared_ptr<const OccupancyGrid> grid, const CostmapOptions& options);

  const OccupancyGrid& grid() const { return *grid_; }
  const CostmapOptions& options() const { return options_; }
  int width() const { return grid_->width(); }
  int height() const { return grid_->height(); }
  bool IsLethal(const CellIndex& c) const { return lethal_[grid_->Flat(c)] != 0; }
  // Row-major lethal flags (1 = lethal), for search inner loops.
  const uint8_t* lethal_data() const { return lethal_.data(); }
  // True when the straight segment a-b (map frame) crosses no lethal cell and stays in the map;
  // at an exact corner crossing both side cells must be free.
  bool SegmentFree(const Point2& a, const Point2& b) const;

 private:
  std::shared_ptr<const OccupancyGrid> grid_;
  CostmapOptions options_;
  std::vector<uint8_t> lethal_;
};

}  // namespace navd::planning
