#pragma once
// Planar geometry in one place. Units: metres and radians; angles counter-clockwise from +x.
#include <Eigen/Core>
#include <cmath>
#include <string>

namespace navd {

using Point2 = Eigen::Vector2d;

// Wraps an angle to (-pi, pi].
inline double NormalizeAngle(double a) {
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  if (a <= 0.0) a += 2.0 * M_PI;
  return a - M_PI;
}

// Pose of a frame in a parent frame: p_parent = R(theta) * p_child + (x, y).
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;

  // Spelled out, so that Pose2(x, y, theta) also builds with clang 14 (the fuzzers, clang-tidy),
  // which lacks C++20's parenthesised aggregate initialisation.
  constexpr Pose2() = default;
  constexpr Pose2(double x_, double y_, double theta_) : x(x_), y(y_), theta(theta_) {}

  Point2 translation() const { return {x, y}; }

  // this ∘ other: other expressed in this pose's parent frame.
  Pose2 operator*(const Pose2& o) const {
    const double c = std::cos(theta), s = std::sin(theta);
    return {x + c * o.x - s * o.y, y + s * o.x + c * o.y, NormalizeAngle(theta + o.theta)};
  }
  Point2 operator*(const Point2& p) const {
    const double c = std::cos(theta), s = std::sin(theta);
    return {x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y()};
  }
  Pose2 inverse() const {
    const double c = std::cos(theta), s = std::sin(theta);
    return {-c * x - s * y, s * x - c * y, NormalizeAngle(-theta)};
  }
  bool finite() const { return std::isfinite(x) && std::isfinite(y) && std::isfinite(theta); }
};

inline double Distance(const Point2& a, const Point2& b) { return (a - b).norm(); }

// `v` turned counter-clockwise by `angle` (rad): a vector's components in a frame turned so.
inline Point2 Rotate(const Point2& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

// The pose a fraction f of the way from a to b (f in [0, 1]): positions linearly, the heading the
// short way round.
inline Pose2 Interpolate(const Pose2& a, const Pose2& b, double f) {
  return {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y),
          NormalizeAngle(a.theta + f * NormalizeAngle(b.theta - a.theta))};
}

// "(x, y)" with centimetre precision, for error messages.
std::string FormatPoint(const Point2& p);

}  // namespace navd
