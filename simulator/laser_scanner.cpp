#include "simulator/laser_scanner.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace navd::sim {

double LaserScanner::CastRay(const OccupancyGrid& map, const Point2& origin, double angle, double max_range) {
  const double res = map.resolution();
  const double dx = std::cos(angle), dy = std::sin(angle);
  CellIndex c = map.CellOf(origin);
  const int step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  // Ray parameter at the next vertical / horizontal cell boundary, and per cell.
  const Point2 local = (origin - map.origin()) / res;
  const double next_x = dx > 0 ? std::floor(local.x()) + 1 : std::floor(local.x());
  const double next_y = dy > 0 ? std::floor(local.y()) + 1 : std::floor(local.y());
  double t_max_x = dx != 0 ? (next_x - local.x()) * res / dx : inf;
  double t_max_y = dy != 0 ? (next_y - local.y()) * res / dy : inf;
  const double t_dx = dx != 0 ? res / std::abs(dx) : inf;
  const double t_dy = dy != 0 ? res / std::abs(dy) : inf;
  double t = 0.0;
  while (t <= max_range) {
    if (!map.Contains(c) || map.IsOccupied(c)) return t;
    if (t_max_x < t_max_y) {
      t = t_max_x;
      t_max_x += t_dx;
      c.x += step_x;
    } else {
      t = t_max_y;
      t_max_y += t_dy;
      c.y += step_y;
    }
  }
  return max_range;
}

std::vector<float> LaserScanner::Scan(const Pose2& pose, const OccupancyGrid& map, std::mt19937_64& rng) const {
  std::vector<float> ranges(d_.beams);
  std::normal_distribution<double> noise(0.0, d_.noise);
  for (int i = 0; i < d_.beams; ++i) {
    const double a = pose.theta + angle_min() + i * increment();
    const double r = CastRay(map, pose.translation(), a, d_.range_max);
    if (r >= d_.range_max) {
      ranges[i] = static_cast<float>(d_.range_max + 1.0);  // no return
    } else {
      ranges[i] = static_cast<float>(std::clamp(r + (d_.noise > 0 ? noise(rng) : 0.0), d_.range_min, d_.range_max));
    }
  }
  return ranges;
}

}  // namespace navd::sim
