#pragma once
// Differential-drive kinematics (book chapter 1): wheel rim speeds <-> body twist, and exact
// integration of wheel travel along a circular arc. Metres, radians, seconds; body frame x forward.
#include <algorithm>
#include <cmath>

#include "services/common/pose2.h"

namespace navd {

struct WheelSpeeds {
  double left = 0.0;   // m/s at the rim
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

// Moves `pose` by wheel travel d_left, d_right (metres) along the arc they describe.
inline Pose2 IntegrateDiffDrive(const Pose2& pose, double d_left, double d_right, double wheel_base) {
  const double ds = (d_left + d_right) / 2.0;
  const double dtheta = (d_right - d_left) / wheel_base;
  double dx, dy;
  if (std::abs(dtheta) < 1e-9) {
    dx = ds;
    dy = 0.0;
  } else {
    const double r = ds / dtheta;
    dx = r * std::sin(dtheta);
    dy = r * (1.0 - std::cos(dtheta));
  }
  return pose * Pose2{dx, dy, dtheta};
}

}  // namespace navd
