#include "services/localization/odometry_jump_filter.h"

#include <algorithm>
#include <cmath>

namespace navd::localization {

OdometryReading OdometryJumpFilter::Filter(const OdometryReading& reading, bool* jumped) {
  if (jumped) *jumped = false;
  OdometryReading out = reading;
  if (!reading.pose.finite()) return out;  // the localisers refuse it themselves
  if (have_last_) {
    const Pose2 step = last_raw_.pose.inverse() * reading.pose;
    const double dt =
        std::isfinite(reading.stamp - last_raw_.stamp) ? std::max(0.0, reading.stamp - last_raw_.stamp) : 0.0;
    const bool too_far = std::hypot(step.x, step.y) > std::max(limits_.min_distance, limits_.max_speed * dt);
    const bool too_turned = std::abs(step.theta) > std::max(limits_.min_angle, limits_.max_turn_rate * dt);
    if (too_far || too_turned) {
      // Re-base so this reading maps to where the robot was at the last one.
      offset_ = (offset_ * last_raw_.pose) * reading.pose.inverse();
      ++jumps_;
      if (jumped) *jumped = true;
    }
  }
  last_raw_ = reading;
  have_last_ = true;
  out.pose = offset_ * reading.pose;
  return out;
}

}  // namespace navd::localization
