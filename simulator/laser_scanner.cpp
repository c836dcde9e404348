#include "simulator/laser_scanner.h"

#include <algorithm>
#include <cmath>

namespace navd::sim {

std::vector<const Disc*> DiscsWithin(const std::vector<Disc>& discs, const Point2& origin, double max_range, int self) {
  std::vector<const Disc*> out;
  for (const Disc& d : discs) {
    if (d.id != self && Distance(d.centre, origin) < max_range + d.radius) out.push_back(&d);
  }
  return out;
}

double CastAgainstWorld(const RayCaster& world, const std::vector<const Disc*>& nearby, const Point2& origin,
                        double angle, double max_range) {
  double r = world.Cast(origin, angle, max_range);
  if (!nearby.empty()) {
    const Point2 dir(std::cos(angle), std::sin(angle));
    for (const Disc* d : nearby) r = std::min(r, RayDiscDistance(origin, dir, *d));
  }
  return r;
}

std::vector<float> LaserScanner::Scan(const Pose2& pose, const RayCaster& world, const std::vector<Disc>& discs,
                                      int self, std::mt19937_64& rng) const {
  std::vector<float> ranges(d_.beams);
  std::normal_distribution<double> noise(0.0, d_.noise);
  const auto nearby = DiscsWithin(discs, pose.translation(), d_.range_max, self);
  for (int i = 0; i < d_.beams; ++i) {
    const double a = pose.theta + angle_min() + i * increment();
    const double r = CastAgainstWorld(world, nearby, pose.translation(), a, d_.range_max);
    if (r >= d_.range_max) {
      ranges[i] = static_cast<float>(d_.range_max + 1.0);  // no return
    } else {
      ranges[i] = static_cast<float>(std::clamp(r + (d_.noise > 0 ? noise(rng) : 0.0), d_.range_min, d_.range_max));
    }
  }
  return ranges;
}

}  // namespace navd::sim
