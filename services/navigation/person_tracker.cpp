#include "services/navigation/person_tracker.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <tuple>

namespace navd::navigation {

double FilteredOrientation(double orientation, const Point2& velocity, double min_direction_speed) {
  const double speed = velocity.norm();
  if (!(speed > min_direction_speed)) return orientation;
  const double heading = std::atan2(velocity.y(), velocity.x());
  return NormalizeAngle(orientation + (1.0 - OrientationBeta(speed)) * NormalizeAngle(heading - orientation));
}

double OrientationBeta(double speed) {
  if (speed < 0.1) return 0.9;
  if (speed <= 0.6) return 1.04 - 1.4 * speed;
  return 0.2;
}

double VelocityStd(const TrackedPerson& t) {
  // The larger eigenvalue of the symmetric 2x2 velocity block.
  const double a = t.covariance(2, 2), b = t.covariance(2, 3), d = t.covariance(3, 3);
  return std::sqrt(std::max(0.0, 0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + b * b)));
}

void PersonTracker::Predict(TrackedPerson& t, double dt) const {
  if (dt <= 0.0) return;
  Eigen::Matrix4d f = Eigen::Matrix4d::Identity();
  f(0, 2) = f(1, 3) = dt;
  // Discrete white-noise acceleration.
  const double q = o_.acceleration_std * o_.acceleration_std;
  Eigen::Matrix4d Q = Eigen::Matrix4d::Zero();
  const double dt2 = dt * dt, dt3 = dt2 * dt / 2.0, dt4 = dt2 * dt2 / 4.0;
  for (int a = 0; a < 2; ++a) {
    Q(a, a) = dt4 * q;
    Q(a, a + 2) = Q(a + 2, a) = dt3 * q;
    Q(a + 2, a + 2) = dt2 * q;
  }
  t.position += dt * t.velocity;
  t.covariance = f * t.covariance * f.transpose() + Q;
}

void PersonTracker::Update(const std::vector<Point2>& detections, double now) {
  const double dt = last_update_ < 0.0 ? 0.0 : std::max(0.0, now - last_update_);
  last_update_ = now;
  for (TrackedPerson& t : tracks_) Predict(t, dt);

  // Nearest pairs first.
  std::vector<std::tuple<double, size_t, size_t>> pairs;
  for (size_t i = 0; i < tracks_.size(); ++i)
    for (size_t j = 0; j < detections.size(); ++j) {
      const double d = Distance(tracks_[i].position, detections[j]);
      if (d <= o_.gate) pairs.emplace_back(d, i, j);
    }
  std::sort(pairs.begin(), pairs.end());
  std::vector<bool> track_used(tracks_.size(), false), detection_used(detections.size(), false);
  const double r = o_.measurement_std * o_.measurement_std;
  for (const auto& [d, i, j] : pairs) {
    if (track_used[i] || detection_used[j]) continue;
    track_used[i] = detection_used[j] = true;
    TrackedPerson& t = tracks_[i];
    // H = [I 0]: the filter sees the position.
    const Eigen::Matrix2d s = t.covariance.topLeftCorner<2, 2>() + r * Eigen::Matrix2d::Identity();
    const Eigen::Matrix<double, 4, 2> k = t.covariance.leftCols<2>() * s.inverse();
    const Eigen::Vector2d innovation = detections[j] - t.position;
    Eigen::Vector4d x;
    x << t.position, t.velocity;
    x += k * innovation;
    t.position = x.head<2>();
    t.velocity = x.tail<2>();
    const double speed = t.velocity.norm();
    if (speed > o_.max_speed) t.velocity *= o_.max_speed / speed;
    t.covariance = (Eigen::Matrix4d::Identity() - k * Eigen::Matrix<double, 2, 4>::Identity()) * t.covariance;
    t.orientation = FilteredOrientation(t.orientation, t.velocity, o_.min_direction_speed);
    ++t.hits;
    t.last_seen = now;
    if (t.hits >= o_.confirm_hits) t.confirmed = true;
  }
  std::erase_if(tracks_, [&](const TrackedPerson& t) { return now - t.last_seen > o_.forget_after; });
  for (size_t j = 0; j < detections.size(); ++j) {
    if (detection_used[j]) continue;
    TrackedPerson t;
    t.id = next_id_++;
    t.position = detections[j];
    t.covariance = Eigen::Matrix4d::Zero();
    t.covariance(0, 0) = t.covariance(1, 1) = r;
    t.covariance(2, 2) = t.covariance(3, 3) = o_.initial_speed_std * o_.initial_speed_std;
    t.hits = 1;
    t.first_seen = t.last_seen = now;
    t.confirmed = o_.confirm_hits <= 1;
    tracks_.push_back(t);
  }
}

std::vector<TrackedPerson> PersonTracker::People(double now) const {
  std::vector<TrackedPerson> out;
  for (TrackedPerson t : tracks_) {
    if (!t.confirmed) continue;
    Predict(t, now - last_update_);
    out.push_back(t);
  }
  return out;
}

}  // namespace navd::navigation
