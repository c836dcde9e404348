#include "services/common/disc.h"

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

}  // namespace navd
