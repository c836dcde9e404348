#include "simulator/laser_scanner.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "services/common/grid_traversal.h"

namespace navd::sim {

double LaserScanner::CastRay(const OccupancyGrid& map, const Point2& origin, double angle, double max_range) {
  double hit = max_range;
  TraverseSegment(map, origin, origin + max_range * Point2(std::cos(angle), std::sin(angle)),
                  [&](const CellIndex& c, double t) {
                    if (map.Contains(c) && !map.IsOccupied(c)) return true;
                    hit = std::min(hit, t);
                    return false;
                  });
  return hit;
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
