#include "services/common/occupancy_grid.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace navd {

OccupancyGrid::OccupancyGrid(int width, int height, double resolution, Point2 origin, int8_t fill)
    : width_(width),
      height_(height),
      resolution_(resolution),
      origin_(std::move(origin)),
      cells_(static_cast<size_t>(width) * height, fill) {}

namespace {
// Casting a double beyond int's range is undefined; NaN lands at the low end.
int ClampToCell(double v) {
  constexpr double kLimit = 1e9;
  if (!(v > -kLimit)) return static_cast<int>(-kLimit);
  if (!(v < kLimit)) return static_cast<int>(kLimit);
  return static_cast<int>(v);
}
}  // namespace

CellIndex OccupancyGrid::CellOf(const Point2& p) const {
  return {ClampToCell(std::floor((p.x() - origin_.x()) / resolution_)),
          ClampToCell(std::floor((p.y() - origin_.y()) / resolution_))};
}

bool OccupancyGrid::DiscHitsObstacle(const Point2& p, double radius) const {
  if (!p.allFinite()) return true;
  const CellIndex lo = CellOf(p - Point2(radius, radius)), hi = CellOf(p + Point2(radius, radius));
  for (int y = lo.y; y <= hi.y; ++y) {
    for (int x = lo.x; x <= hi.x; ++x) {
      if (DistanceToCell(p, {x, y}) >= radius) continue;
      if (!Contains({x, y}) || IsOccupied({x, y})) return true;
    }
  }
  return false;
}

Point2 OccupancyGrid::CellCenter(const CellIndex& c) const {
  return {origin_.x() + (c.x + 0.5) * resolution_, origin_.y() + (c.y + 0.5) * resolution_};
}

double OccupancyGrid::DistanceToCell(const Point2& p, const CellIndex& c) const {
  const Point2 centre = CellCenter(c);
  const double h = resolution_ / 2;
  return std::hypot(std::max(std::abs(p.x() - centre.x()) - h, 0.0), std::max(std::abs(p.y() - centre.y()) - h, 0.0));
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

void OccupancyGrid::FillDisc(const Point2& centre, double radius, int8_t value) {
  const CellIndex lo = CellOf(centre - Point2(radius, radius));
  const CellIndex hi = CellOf(centre + Point2(radius, radius));
  for (int y = std::max(lo.y, 0); y <= std::min(hi.y, height_ - 1); ++y) {
    for (int x = std::max(lo.x, 0); x <= std::min(hi.x, width_ - 1); ++x) {
      if ((CellCenter({x, y}) - centre).squaredNorm() <= radius * radius) set({x, y}, value);
    }
  }
}

}  // namespace navd
