#include "services/common/disc.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace navd {

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

std::vector<const Disc*> DiscsWithin(const std::vector<Disc>& discs, const Point2& origin, double max_range, int self) {
  std::vector<const Disc*> out;
  for (const Disc& d : discs) {
    if (d.id != self && Distance(d.centre, origin) < max_range + d.radius) out.push_back(&d);
  }
  return out;
}

double CastAgainstWorld(const RayCaster& world, const std::vector<const Disc*>& nearby, const Point2& origin,
                        const Point2& dir, double max_range) {
  double r = world.CastOpenEdge(origin, dir, max_range);
  for (const Disc* d : nearby) r = std::min(r, RayDiscDistance(origin, dir, *d));
  return r;
}

}  // namespace navd
