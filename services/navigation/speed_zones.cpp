#include "services/navigation/speed_zones.h"

#include <algorithm>
#include <cmath>

#include "services/common/error.h"
#include "services/common/polygon.h"

namespace navd::navigation {

SpeedZones::SpeedZones(std::vector<SpeedZone> zones) : zones_(std::move(zones)) {
  for (size_t i = 0; i < zones_.size(); ++i) {
    const std::string field = "zones[" + std::to_string(i) + "]";
    const SpeedZone& z = zones_[i];
    if (z.name.empty()) throw Error(ErrorCode::kInvalidArgument, field + ".name is empty");
    for (size_t j = 0; j < i; ++j) {
      if (zones_[j].name == z.name) {
        throw Error(ErrorCode::kInvalidArgument, field + ".name '" + z.name + "' names two zones");
      }
    }
    for (const Point2& p : z.area) {
      if (!p.allFinite()) throw Error(ErrorCode::kInvalidArgument, field + ".area has a non-finite vertex");
    }
    if (auto defect = PolygonDefect(z.area)) {
      throw Error(ErrorCode::kInvalidArgument, field + ".area is not a simple closed curve: it " + *defect);
    }
    if (!(z.max_speed > 0.0) || !std::isfinite(z.max_speed)) {
      throw Error(ErrorCode::kInvalidArgument, field + ".max_speed must be a positive number of m/s");
    }
  }
}

double SpeedZones::LimitAt(const Pose2& pose, double radius, const SpeedZoneOptions& options) const {
  double limit = std::numeric_limits<double>::infinity();
  if (zones_.empty()) return limit;
  const Point2 heading(std::cos(pose.theta), std::sin(pose.theta));
  // Samples along the heading a quarter of the radius apart: a zone is never missed by more.
  const double step = std::max(0.02, 0.25 * radius);
  for (const SpeedZone& z : zones_) {
    for (double d = 0.0; d <= options.look_ahead + 1e-9; d += step) {
      const Point2 p = pose.translation() + d * heading;
      if (!PolygonContains(z.area, p) && DistanceToBoundary(z.area, p) > radius) continue;
      // The first sample ahead that touches the zone: the robot may be faster here by what it can
      // shed over the distance between.
      limit = std::min(limit, std::sqrt(z.max_speed * z.max_speed + 2.0 * options.deceleration * d));
      break;
    }
  }
  return limit;
}

WheelSpeeds SpeedZones::Cap(const WheelSpeeds& wheels, double limit) {
  const double fastest = std::max(std::abs(wheels.left), std::abs(wheels.right));
  if (!(fastest > limit)) return wheels;
  const double k = limit / fastest;
  return {wheels.left * k, wheels.right * k};
}

}  // namespace navd::navigation
