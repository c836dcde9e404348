#include "services/planning/costmap.h"

#include <cmath>

#include "services/common/grid_traversal.h"

namespace navd::planning {

Costmap::Costmap(std::shared_ptr<const OccupancyGrid> grid_ptr, const CostmapOptions& options)
    : grid_(std::move(grid_ptr)), options_(options), lethal_(grid_->cells().size(), 0) {
  const OccupancyGrid& grid = *grid_;
  const int w = grid.width(), h = grid.height();
  const int r = static_cast<int>(std::floor(options.inflation_radius / grid.resolution() + 1e-9));
  const double r2 = std::pow(options.inflation_radius / grid.resolution() + 1e-9, 2);
  // The disc of cell offsets within the radius, stamped around every obstacle cell on an
  // obstacle's boundary (interior cells add nothing their neighbours do not).
  std::vector<CellIndex> disc;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx)
      if (dx * dx + dy * dy <= r2) disc.push_back({dx, dy});

  auto blocked = [&](int x, int y) {
    const int8_t v = grid.at({x, y});
    return v >= OccupancyGrid::kOccupiedThreshold || (v < 0 && options.unknown_is_lethal);
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (!blocked(x, y)) continue;
      lethal_[grid.Flat({x, y})] = 1;
      const bool interior = x > 0 && y > 0 && x < w - 1 && y < h - 1 && blocked(x - 1, y) && blocked(x + 1, y) &&
                            blocked(x, y - 1) && blocked(x, y + 1);
      if (interior) continue;
      for (const auto& d : disc) {
        const CellIndex c{x + d.x, y + d.y};
        if (grid.Contains(c)) lethal_[grid.Flat(c)] = 1;
      }
    }
  }
}

bool Costmap::SegmentFree(const Point2& a, const Point2& b) const {
  return TraverseSegment(*grid_, a, b,
                         [this](const CellIndex& c, double) { return grid_->Contains(c) && !IsLethal(c); });
}

}  // namespace navd::planning
