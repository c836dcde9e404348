#include "services/planning/velocity_profile.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "services/common/error.h"

namespace navd::planning {
namespace {

constexpr double kGravity = 9.81;  // m/s^2
constexpr double kFlat = 1e-9;     // 1/m: curvature below this is a straight line

void Check(double value, const char* name, bool zero_ok = false) {
  if (!std::isfinite(value) || value < 0.0 || (!zero_ok && value == 0.0)) {
    throw Error(ErrorCode::kInvalidArgument, std::string("velocity limits: ") + name + " must be a " +
                                                 (zero_ok ? "non-negative" : "positive") + " number");
  }
}

// Points every `step` metres along the polyline, its first and last points included.
std::vector<Point2> Resample(const std::vector<Point2>& path, double step, std::vector<double>* arc) {
  std::vector<Point2> out{path.front()};
  arc->assign(1, 0.0);
  double travelled = 0.0, next = step;
  for (size_t i = 1; i < path.size(); ++i) {
    const Point2 &a = path[i - 1], &b = path[i];
    const double len = (b - a).norm();
    while (len > 0.0 && next <= travelled + len - 1e-9) {
      out.emplace_back(a + (b - a) * ((next - travelled) / len));
      arc->push_back(next);
      next += step;
    }
    travelled += len;
  }
  if (travelled > arc->back() + 1e-9) {
    out.push_back(path.back());
    arc->push_back(travelled);
  }
  return out;
}

// Signed curvature at each point from its neighbours (the circle through three points).
std::vector<double> Curvature(const std::vector<Point2>& p) {
  std::vector<double> k(p.size(), 0.0);
  for (size_t i = 1; i + 1 < p.size(); ++i) {
    const Point2 a = p[i] - p[i - 1], b = p[i + 1] - p[i], c = p[i + 1] - p[i - 1];
    const double denominator = a.norm() * b.norm() * c.norm();
    if (denominator > 0.0) k[i] = 2.0 * (a.x() * b.y() - a.y() * b.x()) / denominator;
  }
  if (p.size() > 2) {
    k.front() = k[1];
    k.back() = k[p.size() - 2];
  }
  return k;
}

}  // namespace

VelocityProfile TimeOptimalProfile(const std::vector<Point2>& path, const VelocityLimits& l) {
  Check(l.max_speed, "max_speed");
  Check(l.max_acceleration, "max_acceleration");
  Check(l.friction, "friction");
  Check(l.max_angular_acceleration, "max_angular_acceleration");
  Check(l.start_speed, "start_speed", true);
  Check(l.step, "step");
  VelocityProfile out;
  if (path.empty()) return out;
  out.points = Resample(path, l.step, &out.arc);
  const size_t n = out.points.size();
  out.speed.assign(n, 0.0);
  out.time.assign(n, 0.0);
  if (n == 1) return out;
  const std::vector<double> k = Curvature(out.points);
  std::vector<double> dk(n, 0.0);  // dk/ds by central differences
  for (size_t i = 0; i < n; ++i) {
    const size_t a = i == 0 ? 0 : i - 1, b = std::min(n - 1, i + 1);
    if (out.arc[b] > out.arc[a]) dk[i] = (k[b] - k[a]) / (out.arc[b] - out.arc[a]);
  }
  // Eqs. 7-8: the top speed at each point.
  std::vector<double> top(n, l.max_speed);
  for (size_t i = 0; i < n; ++i) {
    if (std::abs(k[i]) > kFlat) top[i] = std::min(top[i], std::sqrt(kGravity * l.friction / std::abs(k[i])));
    if (std::abs(dk[i]) > kFlat) top[i] = std::min(top[i], std::sqrt(l.max_angular_acceleration / std::abs(dk[i])));
  }
  // Eqs. 13-14: how hard the robot may speed up or brake at point i moving at v. The torque term
  // matters on curves only (on a straight line the steering needs no torque).
  auto accel = [&](size_t i, double v, double sign) {
    double a = l.max_acceleration;
    if (std::abs(k[i]) > kFlat) {
      const double torque = l.max_angular_acceleration / std::abs(k[i]) - sign * v * v / k[i] * dk[i];
      a = std::min(a, std::max(0.0, torque));
    }
    return a;
  };
  // Eq. 15, forward from the start speed; Eq. 16, backward from rest at the end.
  std::vector<double> forward(n), backward(n);
  forward[0] = std::min(l.start_speed, top[0]);
  for (size_t i = 1; i < n; ++i) {
    const double ds = out.arc[i] - out.arc[i - 1];
    forward[i] =
        std::min(top[i], std::sqrt(forward[i - 1] * forward[i - 1] + 2.0 * accel(i - 1, forward[i - 1], 1.0) * ds));
  }
  backward[n - 1] = 0.0;
  for (size_t i = n - 1; i-- > 0;) {
    const double ds = out.arc[i + 1] - out.arc[i];
    backward[i] =
        std::min(top[i], std::sqrt(backward[i + 1] * backward[i + 1] + 2.0 * accel(i + 1, backward[i + 1], -1.0) * ds));
  }
  for (size_t i = 0; i < n; ++i) out.speed[i] = std::min(forward[i], backward[i]);
  for (size_t i = 1; i < n; ++i) {
    const double ds = out.arc[i] - out.arc[i - 1];
    const double mean = 0.5 * (out.speed[i - 1] + out.speed[i]);
    out.time[i] = out.time[i - 1] + (mean > 0.0 ? ds / mean : 0.0);
  }
  out.duration = out.time.back();
  return out;
}

namespace {
std::vector<double> AtPathPoints(const std::vector<Point2>& path, const VelocityProfile& profile,
                                 const std::vector<double>& values) {
  std::vector<double> out;
  if (profile.arc.empty()) return std::vector<double>(path.size(), 0.0);
  double s = 0.0;
  size_t j = 0;
  for (size_t i = 0; i < path.size(); ++i) {
    if (i > 0) s += (path[i] - path[i - 1]).norm();
    while (j + 1 < profile.arc.size() && std::abs(profile.arc[j + 1] - s) <= std::abs(profile.arc[j] - s)) ++j;
    out.push_back(values[j]);
  }
  return out;
}
}  // namespace

std::vector<double> SpeedsAtPathPoints(const std::vector<Point2>& path, const VelocityProfile& profile) {
  return AtPathPoints(path, profile, profile.speed);
}

std::vector<double> TimesAtPathPoints(const std::vector<Point2>& path, const VelocityProfile& profile) {
  return AtPathPoints(path, profile, profile.time);
}

}  // namespace navd::planning
