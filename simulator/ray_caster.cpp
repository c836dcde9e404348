#include "simulator/ray_caster.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "services/common/grid_traversal.h"

namespace navd::sim {
namespace {

// A point anywhere in a cell whose centre is D cells from the nearest obstacle centre is at least
// D - sqrt(2) cells from any point of that obstacle's square: half a diagonal for each square.
constexpr float kSafeMargin = 1.4143f;
// Below this clearance (cells) a leap would be shorter than a few cell steps: walk instead.
constexpr float kLeapThreshold = 3.0f;
constexpr double kWalkCells = 4.0;

}  // namespace

RayCaster::RayCaster(OccupancyGrid grid) : grid_(std::move(grid)) {
  const DistanceField field(grid_);
  clearance_.resize(field.values().size());
  const double inv = 1.0 / grid_.resolution();
  for (size_t i = 0; i < clearance_.size(); ++i) {
    const double d = field.values()[i];
    clearance_[i] = std::isfinite(d) ? static_cast<float>(d * inv) : 1e9f;
  }
  // The map's edge is a wall too: clearance can be no larger than the distance to just outside it.
  for (int y = 0; y < grid_.height(); ++y) {
    for (int x = 0; x < grid_.width(); ++x) {
      const int edge = std::min({x + 1, y + 1, grid_.width() - x, grid_.height() - y});
      float& c = clearance_[static_cast<size_t>(y) * grid_.width() + x];
      c = std::min(c, static_cast<float>(edge));
    }
  }
}

double RayCaster::Clearance(const Point2& p) const {
  const CellIndex c = grid_.CellOf(p);
  if (!grid_.Contains(c)) return 0.0;
  return clearance_[grid_.Flat(c)] * grid_.resolution();
}

double RayCaster::Cast(const Point2& origin, double angle, double max_range) const {
  const Point2 dir(std::cos(angle), std::sin(angle));
  const double res = grid_.resolution();
  double t = 0.0;
  while (t < max_range) {
    const Point2 p = origin + t * dir;
    const CellIndex c = grid_.CellOf(p);
    if (!grid_.Contains(c)) return t;
    const float clearance = clearance_[grid_.Flat(c)];
    if (clearance >= kLeapThreshold) {
      t += (clearance - kSafeMargin) * res;
      continue;
    }
    const double end = std::min(max_range, t + kWalkCells * res);
    double hit = -1.0;
    TraverseSegment(grid_, p, origin + end * dir, [&](const CellIndex& cell, double s) {
      if (grid_.Contains(cell) && !grid_.IsOccupied(cell)) return true;
      hit = t + s;
      return false;
    });
    if (hit >= 0.0) return std::min(hit, max_range);
    t = end;
  }
  return max_range;
}

bool RayCaster::DiscHitsWall(const Point2& p, double radius) const {
  const CellIndex c = grid_.CellOf(p);
  if (!p.allFinite() || !grid_.Contains(c)) return true;
  // Clear by a cell's diagonal more than the radius: no occupied square can reach the disc.
  if ((clearance_[grid_.Flat(c)] - kSafeMargin) * grid_.resolution() > radius) return false;
  return grid_.DiscHitsObstacle(p, radius);
}

double RayDiscDistance(const Point2& origin, const Point2& dir, const Disc& disc) {
  const Point2 m = origin - disc.centre;
  const double b = m.dot(dir);
  const double c = m.squaredNorm() - disc.radius * disc.radius;
  if (c <= 0.0) return std::numeric_limits<double>::infinity();  // inside: the sensor is in the body
  if (b > 0.0) return std::numeric_limits<double>::infinity();   // pointing away
  const double disc_term = b * b - c;
  if (disc_term < 0.0) return std::numeric_limits<double>::infinity();
  return -b - std::sqrt(disc_term);
}

}  // namespace navd::sim
