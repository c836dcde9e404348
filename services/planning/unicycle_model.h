#pragma once
// Book chapter 7's robot (Sec. 7.1, Eq. 10): a unicycle driven by accelerations,
//   ẋ = v cos θ,  ẏ = v sin θ,  v̇ = u_v,  θ̇ = ω,  ω̇ = u_ω,
// and the steering of its RRT's CalculateControlInput (Eq. 16, without the noise, which the
// planners add). Shared by the OMPL kinodynamic planner and the crowd RRT so both plan for the
// same robot. Map frame, metres, radians, seconds.
#include "services/common/pose2.h"

namespace navd::planning {

struct UnicycleLimits {
  double max_speed = 0.5;      // m/s, forward only (the chapter prunes heading back)
  double max_yaw_rate = 1.5;   // rad/s
  double max_accel = 0.5;      // m/s²
  double max_yaw_accel = 2.0;  // rad/s²
};

struct UnicycleState {
  double x = 0.0, y = 0.0;  // m, map frame
  double yaw = 0.0;         // rad
  double v = 0.0;           // m/s
  double w = 0.0;           // rad/s
  double t = 0.0;           // s since the plan's start
  Point2 position() const { return {x, y}; }
};

struct UnicycleInput {
  double accel = 0.0;      // u_v, m/s²
  double yaw_accel = 0.0;  // u_ω, rad/s²
};

// Eq. 16's gains (the chapter leaves them to Svenstrup et al. 2010): speed P, heading PD. With
// these the heading loop is s² + 3 s + 4, well damped.
struct SteeringGains {
  double speed = 1.0;     // k_v, 1/s
  double heading = 4.0;   // k_θ1, 1/s²
  double yaw_rate = 3.0;  // k_θ2, 1/s
};

// Eq. 16 without noise: towards `desired_speed` and towards the bearing of `target`.
UnicycleInput SteerTowards(const UnicycleState& s, const Point2& target, double desired_speed,
                           const SteeringGains& gains);
UnicycleInput ClampInput(const UnicycleInput& u, const UnicycleLimits& limits);
// Full braking, the yaw rate damped to nought within `step` seconds: the crowd planner's braking
// chain, and what follows each escape (and a short plan) when the escapes are judged.
UnicycleInput Braking(const UnicycleState& s, const UnicycleLimits& limits, double step);
// One Euler step of Eq. 10 of `dt` seconds; the input is clamped to the limits, the speed to
// [0, max_speed] and the yaw rate to ±max_yaw_rate.
UnicycleState Propagate(const UnicycleState& s, const UnicycleInput& u, double dt, const UnicycleLimits& limits);

}  // namespace navd::planning
