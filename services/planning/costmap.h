#pragma once
// A planning costmap, like Nav2's inflation layer: cells within `inflation_radius` metres (centre
// to centre) of an occupied cell are lethal; beyond that, within `decay_radius` more, a cost falls
// off exponentially with distance, cost = 252 * exp(-cost_scaling * (d - inflation_radius)), so
// cost-aware planners keep clear of walls when there is room. Unknown cells are lethal unless
// allowed. Costs are 0..252 (free..nearly lethal); lethal cells are flagged separately.
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "services/common/occupancy_grid.h"

namespace navd::planning {

struct CostmapOptions {
  double inflation_radius = 0.30;  // metres: robot radius + margin
  bool unknown_is_lethal = true;
  double decay_radius = 0.0;  // metres of decaying cost beyond the inflation radius (0: none)
  double cost_scaling = 3.0;  // 1/m, Nav2's cost_scaling_factor
};

class Costmap {
 public:
  static constexpr uint8_t kMaxCost = 252;

  // Shares ownership of the grid, so a costmap outlives a map swap.
  Costmap(std::shared_ptr<const OccupancyGrid> grid, const CostmapOptions& options);

  const OccupancyGrid& grid() const { return *grid_; }
  // The shared grid itself, for caches that must tell one map from the next.
  const std::shared_ptr<const OccupancyGrid>& grid_ptr() const { return grid_; }
  const CostmapOptions& options() const { return options_; }
  int width() const { return grid_->width(); }
  int height() const { return grid_->height(); }
  bool IsLethal(const CellIndex& c) const { return lethal_[grid_->Flat(c)] != 0; }
  // Row-major lethal flags (1 = lethal), for search inner loops.
  const uint8_t* lethal_data() const { return lethal_.data(); }
  // Row-major move masks, for search inner loops: bit k of a cell's mask is set when the grid move
  // kGridMoves[k] (grid_moves.h) is allowed from it: the target is in the map and not lethal, and
  // for a diagonal move both side cells are not lethal either. 0 for lethal cells. One byte read
  // per expansion replaces up to 24 cell and bounds tests.
  const uint8_t* move_data() const { return moves_.data(); }
  // Decaying cost of a non-lethal cell, 0..kMaxCost; all zero without decay.
  uint8_t cost(const CellIndex& c) const { return cost_.empty() ? 0 : cost_[grid_->Flat(c)]; }
  // Metres from the cell's centre to the nearest obstacle's (infinity when there is none), kept
  // from construction so planners that weigh clearance do not recompute it per request.
  double distance(size_t flat_index) const { return distance_[flat_index]; }
  // Row-major costs, or nullptr when the costmap has no decay layer.
  const uint8_t* cost_data() const { return cost_.empty() ? nullptr : cost_.data(); }
  // True when the straight segment a-b (map frame) crosses no lethal cell and stays in the map;
  // at an exact corner crossing both side cells must be free.
  bool SegmentFree(const Point2& a, const Point2& b) const;
  // The highest cost on the segment a-b (0 without decay), or -1 when it is not SegmentFree: both
  // answers from one traversal.
  int SegmentMaxCost(const Point2& a, const Point2& b) const;
  // The nearest cell that is not lethal, by a breadth-first search (4-connected) from `from` out to
  // `max_cells` cells along either axis; nullopt when there is none that near. through_obstacles
  // false: the search does not cross occupied cells, so the answer is reachable from `from`; true:
  // it does (where to head from a pose estimate that lies inside a wall).
  std::optional<CellIndex> NearestFree(const CellIndex& from, int max_cells, bool through_obstacles) const;

 private:
  void BuildMoveMasks();

  std::shared_ptr<const OccupancyGrid> grid_;
  CostmapOptions options_;
  std::vector<uint8_t> lethal_;
  std::vector<uint8_t> moves_;
  std::vector<uint8_t> cost_;
  std::vector<float> distance_;
};

}  // namespace navd::planning
