#include "simulator/ray_caster.h"

#include <algorithm>
#include <cmath>
#include <limits>


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
  const int width = grid_.width(), height = grid_.height();
  const int8_t* cells = grid_.cells().data();
  const float* clearance = clearance_.data();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const int step_x = dir.x() > 0 ? 1 : -1, step_y = dir.y() > 0 ? 1 : -1;
  const double dt_x = dir.x() != 0 ? res / std::abs(dir.x()) : kInf;
  const double dt_y = dir.y() != 0 ? res / std::abs(dir.y()) : kInf;
  const double corner_tolerance = 1e-9 * res;
  auto blocked = [&](int x, int y) {
    return x < 0 || y < 0 || x >= width || y >= height ||
           cells[static_cast<size_t>(y) * width + x] >= OccupancyGrid::kOccupiedThreshold;
  };
  double t = 0.0;
  while (t < max_range) {
    const Point2 p = origin + t * dir;
    const CellIndex c = grid_.CellOf(p);
    if (!grid_.Contains(c)) return t;
    const float room = clearance[grid_.Flat(c)];
    if (room >= kLeapThreshold) {
      t += (room - kSafeMargin) * res;
      continue;
    }
    if (blocked(c.x, c.y)) return t;
    // Walk a few cells exactly (the same rule as TraverseSegment, corners included), then look
    // whether there is room to leap again.
    const Point2 local = (p - grid_.origin()) / res;
    const double next_x = dir.x() > 0 ? std::floor(local.x()) + 1 : std::floor(local.x());
    const double next_y = dir.y() > 0 ? std::floor(local.y()) + 1 : std::floor(local.y());
    double t_x = dir.x() != 0 ? t + (next_x - local.x()) * res / dir.x() : kInf;
    double t_y = dir.y() != 0 ? t + (next_y - local.y()) * res / dir.y() : kInf;
    int x = c.x, y = c.y;
    const double end = std::min(max_range, t + kWalkCells * res);
    while (true) {
      if (std::abs(t_x - t_y) <= corner_tolerance) {
        const double tc = std::min(t_x, t_y);
        if (tc > end) break;
        if (blocked(x + step_x, y) || blocked(x, y + step_y)) return std::min(tc, max_range);
        x += step_x;
        y += step_y;
        t_x += dt_x;
        t_y += dt_y;
        if (blocked(x, y)) return std::min(tc, max_range);
      } else if (t_x < t_y) {
        if (t_x > end) break;
        x += step_x;
        if (blocked(x, y)) return std::min(t_x, max_range);
        t_x += dt_x;
      } else {
        if (t_y > end) break;
        y += step_y;
        if (blocked(x, y)) return std::min(t_y, max_range);
        t_y += dt_y;
      }
    }
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
