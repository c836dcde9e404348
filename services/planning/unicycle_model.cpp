#include "services/planning/unicycle_model.h"

#include <algorithm>
#include <cmath>

namespace navd::planning {

UnicycleInput SteerTowards(const UnicycleState& s, const Point2& target, double desired_speed,
                           const SteeringGains& gains) {
  const double phi = std::atan2(target.y() - s.y, target.x() - s.x);
  const double heading_error = NormalizeAngle(phi - s.yaw);
  return {gains.speed * (desired_speed - s.v), gains.heading * heading_error - gains.yaw_rate * s.w};
}

UnicycleInput ClampInput(const UnicycleInput& u, const UnicycleLimits& l) {
  return {std::clamp(u.accel, -l.max_accel, l.max_accel), std::clamp(u.yaw_accel, -l.max_yaw_accel, l.max_yaw_accel)};
}

UnicycleInput Braking(const UnicycleState& s, const UnicycleLimits& limits, double step) {
  return {-limits.max_accel, -s.w / step};
}

UnicycleState Propagate(const UnicycleState& s, const UnicycleInput& input, double dt, const UnicycleLimits& l) {
  const UnicycleInput u = ClampInput(input, l);
  UnicycleState n = s;
  n.x += s.v * std::cos(s.yaw) * dt;
  n.y += s.v * std::sin(s.yaw) * dt;
  n.yaw = NormalizeAngle(s.yaw + s.w * dt);
  n.v = std::clamp(s.v + u.accel * dt, 0.0, l.max_speed);
  n.w = std::clamp(s.w + u.yaw_accel * dt, -l.max_yaw_rate, l.max_yaw_rate);
  n.t += dt;
  return n;
}

}  // namespace navd::planning
