#pragma once
// Differential-drive kinematics (book chapter 1): wheel rim speeds <-> body twist, and exact
// integration of a constant twist along its arc. Metres, radians, seconds; body frame x forward.
#include <algorithm>
#include <cmath>

#include "services/common/pose2.h"

namespace navd {

struct WheelSpeeds {
  double left = 0.0;  // m/s at the rim
  double right = 0.0;
};

struct Twist2 {
  double v = 0.0;      // m/s forward
  double omega = 0.0;  // rad/s counter-clockwise
};

inline Twist2 ToTwist(const WheelSpeeds& w, double wheel_base) {
  return {(w.left + w.right) / 2.0, (w.right - w.left) / wheel_base};
}

inline WheelSpeeds ToWheels(const Twist2& t, double wheel_base) {
  return {t.v - t.omega * wheel_base / 2.0, t.v + t.omega * wheel_base / 2.0};
}

// Scales both wheels by the same factor so neither exceeds `max_speed`, keeping the curvature.
inline WheelSpeeds ClampWheels(const WheelSpeeds& w, double max_speed) {
  const double m = std::max(std::abs(w.left), std::abs(w.right));
  if (m <= max_speed || m == 0.0) return w;
  const double k = max_speed / m;
  return {w.left * k, w.right * k};
}

// Moves `pose` by a constant body twist held for one interval, given as the body-frame travel it
// would make without turning (dx forward, dy left, metres) and the turn dtheta (radians): the exact
// exponential map of SE(2), so arcs stay arcs for any drive (differential or omnidirectional).
inline Pose2 IntegrateTwist(const Pose2& pose, double dx, double dy, double dtheta) {
  if (std::abs(dtheta) < 1e-9) return pose * Pose2{dx, dy, dtheta};
  const double s = std::sin(dtheta), c = 1.0 - std::cos(dtheta);
  return pose * Pose2{(s * dx - c * dy) / dtheta, (c * dx + s * dy) / dtheta, dtheta};
}

// Moves `pose` by wheel travel d_left, d_right (metres) along the arc they describe.
inline Pose2 IntegrateDiffDrive(const Pose2& pose, double d_left, double d_right, double wheel_base) {
  return IntegrateTwist(pose, (d_left + d_right) / 2.0, 0.0, (d_right - d_left) / wheel_base);
}

}  // namespace navd
