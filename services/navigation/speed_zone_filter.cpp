#include "services/navigation/speed_zone_filter.h"

#include <cmath>
#include <limits>

namespace navd::navigation {

WheelSpeeds SpeedZoneFilter::Filter(const WheelSpeeds& wheels, const CommandContext& context) {
  double limit = std::numeric_limits<double>::infinity();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (context.pose_valid) limit = zones_.LimitAt(context.pose, radius_, options_);
  }
  last_limit_ = std::isfinite(limit) ? limit : 0.0;
  return SpeedZones::Cap(wheels, limit);
}

void SpeedZoneFilter::SetZones(SpeedZones zones) {
  std::lock_guard<std::mutex> lock(mutex_);
  zones_ = std::move(zones);
}

SpeedZones SpeedZoneFilter::zones() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return zones_;
}

}  // namespace navd::navigation
