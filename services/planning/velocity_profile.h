#pragma once
// The time-optimal velocity profile of book chapter 9 (Cheng, Jiang and Hu, section 5): the
// fastest speed along a path under a top speed, the friction limit on turning (v^2 |k| <= g mu),
// the steering-torque limit on how fast curvature may change (v^2 <= (tau/J) / |dk/ds|), and
// driving-force and torque limits on acceleration (Eqs. 13-14); from the start speed, ending at
// rest. A forward pass accelerates as hard as allowed (Eq. 15), a backward pass from the end
// brakes as hard as allowed (Eq. 16), and the profile is the lower of the two. Metres, seconds,
// radians; map frame.
#include <vector>

#include "services/common/pose2.h"

namespace navd::planning {

struct VelocityLimits {
  double max_speed = 0.5;                 // m/s
  double max_acceleration = 0.5;          // m/s^2: driving force / mass (F_max / M)
  double friction = 0.6;                  // mu_max: lateral acceleration at most g mu
  double max_angular_acceleration = 6.0;  // rad/s^2: steering torque / inertia (tau_max / J)
  double start_speed = 0.0;               // m/s
  double step = 0.05;                     // m: the arc-length step delta
};

struct VelocityProfile {
  std::vector<Point2> points;  // the path resampled every `step` (first and last point kept)
  std::vector<double> arc;     // m from the start, per point
  std::vector<double> speed;   // m/s, per point; 0 at the end
  std::vector<double> time;    // s from the start, per point
  double duration = 0.0;       // s
};

// Throws navd::Error(kInvalidArgument) naming the limit for non-positive or non-finite limits.
VelocityProfile TimeOptimalProfile(const std::vector<Point2>& path, const VelocityLimits& limits);

// The profile's speed at each of `path`'s own points (nearest resampled point by arc length).
std::vector<double> SpeedsAtPathPoints(const std::vector<Point2>& path, const VelocityProfile& profile);
std::vector<double> TimesAtPathPoints(const std::vector<Point2>& path, const VelocityProfile& profile);

}  // namespace navd::planning
