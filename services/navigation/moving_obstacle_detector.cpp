#include "services/navigation/moving_obstacle_detector.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace navd::navigation {

MovingObstacleDetector::MovingObstacleDetector(const MovingObstacleDetectorOptions& options) : options_(options) {}

void MovingObstacleDetector::Reset() {
  candidates_.clear();
  nearest_.reset();
  last_pose_.reset();
  robot_velocity_ = Point2::Zero();
  danger_ = 0.0;
}

std::vector<DetectedObstacle> MovingObstacleDetector::Segment(const localization::ScanReading& scan,
                                                              const Pose2& pose) const {
  std::vector<DetectedObstacle> found;
  if (!map_ || scan.ranges.empty() || !std::isfinite(scan.angle_increment) || scan.angle_increment == 0.0) {
    return found;
  }
  const Point2 origin = pose.translation();
  const double max_range = scan.range_max > 0.0 ? scan.range_max : 30.0;
  const double increment = std::abs(scan.angle_increment);

  // A run of flagged beams [first, last]: its nearest range and the bearings at its ends.
  size_t first = 0, last = 0;
  double nearest = 0.0;
  bool open = false;
  auto close_run = [&]() {
    open = false;
    if (static_cast<int>(last - first + 1) < options_.min_beams) return;
    // The run spans the disc between its tangent beams: sin(w/2) = R / (d + R) with d the range of
    // its nearest point, so R = d s / (1 - s).
    const double width = static_cast<double>(last - first + 1) * increment;
    const double s = std::min(std::sin(width / 2.0), 0.9);
    const double radius = nearest * s / (1.0 - s);
    const double bearing = scan.angle_min + scan.angle_increment * 0.5 * static_cast<double>(first + last);
    const double heading = pose.theta + bearing;
    const double centre_range = nearest + radius;
    if (centre_range > options_.max_distance || radius < options_.min_radius) return;
    DetectedObstacle o;
    o.position = origin + centre_range * Point2(std::cos(heading), std::sin(heading));
    o.radius = std::min(radius * (1.0 + options_.margin), options_.max_radius);
    found.push_back(o);
  };
  double previous_range = 0.0;
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    bool flagged = false;
    if (std::isfinite(r) && r >= scan.range_min && r < max_range && r <= options_.max_distance) {
      const double angle = pose.theta + scan.angle_min + scan.angle_increment * static_cast<double>(i);
      const double expected = map_->CastOpenEdge(origin, angle, max_range);
      // Something stands where the map knows free space. A map still being built (exploration)
      // has not seen every wall, and its walls shift a little with each loop closure.
      const CellIndex hit = map_->grid().CellOf(origin + r * Point2(std::cos(angle), std::sin(angle)));
      flagged = expected - r > options_.threshold && map_->grid().Contains(hit) && map_->grid().at(hit) >= 0 &&
                !map_->grid().IsOccupied(hit);
    }
    // Two bodies side by side at different depths are two runs.
    if (open && (!flagged || std::abs(r - previous_range) > options_.associate_distance)) close_run();
    if (flagged) {
      if (!open) {
        open = true;
        first = i;
        nearest = r;
      }
      last = i;
      nearest = std::min(nearest, r);
      previous_range = r;
    }
  }
  if (open) close_run();
  return found;
}

void MovingObstacleDetector::Update(const localization::ScanReading& scan, const Pose2& pose, double now) {
  const std::vector<DetectedObstacle> seen = Segment(scan, pose);
  std::vector<bool> matched(candidates_.size(), false);
  std::vector<DetectedObstacle> fresh;
  for (const DetectedObstacle& s : seen) {
    // The candidate nearest to where it should be now, within delta_max.
    long best = -1;
    double best_distance = options_.associate_distance;
    for (size_t k = 0; k < candidates_.size(); ++k) {
      if (matched[k]) continue;
      const DetectedObstacle& c = candidates_[k];
      const Point2 predicted = c.position + c.velocity * std::max(0.0, now - c.last_seen);
      const double d = (predicted - s.position).norm();
      if (d <= best_distance) {
        best_distance = d;
        best = static_cast<long>(k);
      }
    }
    if (best < 0) {
      DetectedObstacle o = s;
      o.probability = options_.p0;
      o.first_seen = o.last_seen = now;
      fresh.push_back(o);
      continue;
    }
    DetectedObstacle& c = candidates_[static_cast<size_t>(best)];
    matched[static_cast<size_t>(best)] = true;
    const double dt = now - c.last_seen;
    if (dt > 1e-6) {
      // Smoothed: a single scan's disc jitters by a few centimetres.
      const Point2 measured = (s.position - c.position) / dt;
      c.velocity = 0.7 * c.velocity + 0.3 * measured;
    }
    c.position = s.position;
    c.radius = 0.5 * (c.radius + s.radius);
    c.last_seen = now;
    // The seed prints max(alpha p, 1), which would jump to 1; a probability is capped at 1.
    c.probability = std::min(options_.alpha * c.probability, 1.0);
  }
  std::vector<DetectedObstacle> kept;
  for (size_t k = 0; k < candidates_.size(); ++k) {
    DetectedObstacle c = candidates_[k];
    if (!matched[k]) c.probability *= options_.beta;
    if (c.probability < options_.p_min) continue;
    if (now - c.first_seen >= options_.dt_confirm) c.confirmed = true;
    kept.push_back(c);
  }
  for (const DetectedObstacle& f : fresh) kept.push_back(f);
  candidates_ = std::move(kept);
  UpdateDanger(pose, now);
}

void MovingObstacleDetector::UpdateDanger(const Pose2& pose, double now) {
  const double dt = now - last_update_;
  if (last_pose_ && dt > 1e-6 && dt < 1.0) {
    robot_velocity_ = 0.5 * robot_velocity_ + 0.5 * (pose.translation() - last_pose_->translation()) / dt;
  } else if (!last_pose_ || dt >= 1.0) {
    robot_velocity_ = Point2::Zero();
  }
  last_pose_ = pose;
  last_update_ = now;

  nearest_.reset();
  double best_m = -1.0, best_distance = std::numeric_limits<double>::infinity();
  for (const DetectedObstacle& c : candidates_) {
    if (!c.confirmed) continue;
    if ((pose.inverse() * c.position).x() <= 0.0) continue;  // behind: the seed handles frontal ones only
    // A thing that stands still is no moving obstacle: the robot's plans go round it (a box the
    // map lacks), and backing away from it would only bring the robot back.
    if (c.velocity.norm() < options_.min_obstacle_speed) continue;
    const Point2 p = c.position - pose.translation();
    const Point2 w = c.velocity - robot_velocity_;
    const double distance = p.norm();
    const double approach = distance > 1e-9 ? -p.dot(w) / distance : 0.0;
    double m = 0.0;
    if (approach > options_.closing_speed) {
      // First t >= 0 with |p + w t| = R: the discs touch.
      const double r = c.radius + options_.robot_radius + options_.contact_margin;
      const double a = w.squaredNorm(), b = p.dot(w), k = p.squaredNorm() - r * r;
      double t = std::numeric_limits<double>::infinity();
      if (k <= 0.0) {
        t = 0.0;
      } else if (b * b - a * k >= 0.0 && a > 1e-12) {
        t = (-b - std::sqrt(b * b - a * k)) / a;
      }
      m = std::clamp((options_.ttc_far - t) / (options_.ttc_far - options_.ttc_near), 0.0, 1.0);
    }
    if (m > best_m || (m == best_m && distance < best_distance)) {
      best_m = m;
      best_distance = distance;
      nearest_ = c;
    }
  }
  danger_ = (1.0 - options_.danger_alpha) * danger_ + options_.danger_alpha * std::max(best_m, 0.0);
}

std::vector<DetectedObstacle> MovingObstacleDetector::confirmed() const {
  std::vector<DetectedObstacle> out;
  for (const DetectedObstacle& c : candidates_)
    if (c.confirmed) out.push_back(c);
  return out;
}

}  // namespace navd::navigation
