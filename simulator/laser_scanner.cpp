#include "simulator/laser_scanner.h"

#include <algorithm>
#include <cmath>

#include "services/common/ziggurat_normal.h"

namespace navd::sim {

LaserScanner::LaserScanner(const LaserDescription& description) : d_(description) {
  beam_directions_.reserve(std::max(d_.beams, 0));
  for (int i = 0; i < d_.beams; ++i) {
    const double a = angle_min() + i * increment();
    beam_directions_.emplace_back(std::cos(a), std::sin(a));
  }
}

std::vector<float> LaserScanner::Scan(const Pose2& pose, const RayCaster& world, const std::vector<Disc>& discs,
                                      int self, std::mt19937_64& rng) const {
  std::vector<float> ranges(d_.beams);
  const ZigguratNormal noise(0.0, d_.noise);
  const auto nearby = DiscsWithin(discs, pose.translation(), d_.range_max, self);
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  for (int i = 0; i < d_.beams; ++i) {
    const Point2& b = beam_directions_[i];
    const Point2 dir(c * b.x() - s * b.y(), s * b.x() + c * b.y());
    const double r = CastAgainstWorld(world, nearby, pose.translation(), dir, d_.range_max);
    if (r >= d_.range_max) {
      ranges[i] = static_cast<float>(d_.range_max + 1.0);  // no return
    } else {
      ranges[i] = static_cast<float>(std::clamp(r + (d_.noise > 0 ? noise(rng) : 0.0), d_.range_min, d_.range_max));
    }
  }
  return ranges;
}

}  // namespace navd::sim
