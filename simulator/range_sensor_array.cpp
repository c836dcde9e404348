#include "simulator/range_sensor_array.h"

#include <algorithm>
#include <cmath>

#include "services/common/sonar_ring.h"
#include "services/common/ziggurat_normal.h"

#include "simulator/laser_scanner.h"

namespace navd::sim {
namespace {
constexpr double kDeg = M_PI / 180.0;
}

RangeArrayDescription PioneerSonarRing(double robot_radius) {
  RangeArrayDescription d;
  d.kind = "sonar";
  d.angles = PioneerSonarAngles();
  d.mount_radius = robot_radius;
  d.cone = kPioneerSonarCone;
  d.rays_per_cone = 5;
  d.range_min = kPioneerSonarRangeMin;
  d.range_max = kPioneerSonarRangeMax;
  d.noise = 0.02;
  d.rate = 10.0;
  return d;
}

RangeArrayDescription Gp2d12Triple(double robot_radius) {
  RangeArrayDescription d;
  d.kind = "ir";
  d.angles = {30 * kDeg, -30 * kDeg, 180 * kDeg};
  d.mount_radius = robot_radius;
  d.cone = 0.0;
  d.rays_per_cone = 1;
  d.range_min = 0.10;
  d.range_max = 0.80;
  d.noise = 0.01;
  d.rate = 25.0;
  return d;
}

std::vector<float> RangeSensorArray::Read(const Pose2& pose, const RayCaster& world, const std::vector<Disc>& discs,
                                          int self, std::mt19937_64& rng) const {
  const ZigguratNormal noise(0.0, d_.noise);
  const auto nearby = DiscsWithin(discs, pose.translation(), d_.mount_radius + d_.range_max, self);
  std::vector<float> out;
  out.reserve(d_.angles.size());
  const int rays = std::max(1, d_.rays_per_cone);
  for (double mount : d_.angles) {
    const double heading = pose.theta + mount;
    const Point2 origin = pose.translation() + d_.mount_radius * Point2(std::cos(heading), std::sin(heading));
    double r = d_.range_max;
    for (int k = 0; k < rays; ++k) {
      const double offset = rays == 1 ? 0.0 : -d_.cone / 2 + k * d_.cone / (rays - 1);
      r = std::min(r, CastAgainstWorld(world, nearby, origin,
                                       Point2(std::cos(heading + offset), std::sin(heading + offset)), d_.range_max));
    }
    if (r < d_.range_max && d_.noise > 0) r += noise(rng);
    out.push_back(static_cast<float>(std::clamp(r, d_.range_min, d_.range_max)));
  }
  return out;
}

}  // namespace navd::sim
