#include "services/navigation/free_way.h"

#include <algorithm>
#include <cmath>

namespace navd::navigation {

std::function<double(double)> FreeAlong(std::vector<Point2> local, double radius) {
  return [local = std::move(local), radius](double bearing) {
    const double c = std::cos(bearing), s = std::sin(bearing);
    double free = 4.0;
    for (const Point2& p : local) {
      const double along = c * p.x() + s * p.y();
      const double lateral = -s * p.x() + c * p.y();
      if (along > 0.0 && std::abs(lateral) < radius + 0.03) free = std::min(free, along - radius);
    }
    return std::max(free, 0.0);
  };
}

WheelSpeeds CapApproach(const WheelSpeeds& wheels, std::vector<Point2> local, double radius, double margin,
                        double deceleration) {
  const double v = 0.5 * (wheels.left + wheels.right);
  if (v <= 0.0 || local.empty()) return wheels;
  const double room = std::max(0.0, FreeAlong(std::move(local), radius)(0.0) - margin);
  const double allowed = std::sqrt(2.0 * deceleration * room);
  if (v <= allowed) return wheels;
  const double k = allowed / v;
  return {wheels.left * k, wheels.right * k};
}

}  // namespace navd::navigation
