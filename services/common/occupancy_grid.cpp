#include "services/common/occupancy_grid.h"

#include <algorithm>
#include <cmath>

namespace navd {

OccupancyGrid::OccupancyGrid(int width, int height, double resolution, Point2 origin, int8_t fill)
    : width_(width), height_(height), resolution_(resolution), origin_(origin),
      cells_(static_cast<size_t>(width) * height, fill) {}

CellIndex OccupancyGrid::CellOf(const Point2& p) const {
  return {static_cast<int>(std::floor((p.x() - origin_.x()) / resolution_)),
          static_cast<int>(std::floor((p.y() - origin_.y()) / resolution_))};
}

Point2 OccupancyGrid::CellCenter(const CellIndex& c) const {
  return {origin_.x() + (c.x + 0.5) * resolution_, origin_.y() + (c.y + 0.5) * resolution_};
}

void OccupancyGrid::FillBox(const Point2& min, const Point2& max, int8_t value) {
  const CellIndex lo = CellOf(min), hi = CellOf(max);
  for (int y = std::max(lo.y, 0); y <= std::min(hi.y, height_ - 1); ++y) {
    for (int x = std::max(lo.x, 0); x <= std::min(hi.x, width_ - 1); ++x) {
      const Point2 c = CellCenter({x, y});
      if (c.x() >= min.x() && c.x() <= max.x() && c.y() >= min.y() && c.y() <= max.y()) set({x, y}, value);
    }
  }
}

}  // namespace navd
