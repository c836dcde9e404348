#include "services/navigation/path_follower.h"

#include <algorithm>
#include <cmath>

namespace navd::navigation {

namespace {
// Bearing of `target` from a robot at `pose` (rad, robot frame): seed 000's heading error dphi.
double BearingOf(const Point2& target, const Pose2& pose) {
  return NormalizeAngle(std::atan2(target.y() - pose.y, target.x() - pose.x) - pose.theta);
}
}  // namespace

std::vector<Point2> DensifyPath(const std::vector<Point2>& path, double spacing) {
  if (path.empty()) return {};
  std::vector<Point2> out{path.front()};
  for (size_t i = 1; i < path.size(); ++i) {
    const Point2 &a = path[i - 1], &b = path[i];
    const int pieces = std::max(1, static_cast<int>(std::ceil(Distance(a, b) / spacing)));
    for (int k = 1; k <= pieces; ++k) out.emplace_back(a + (b - a) * (static_cast<double>(k) / pieces));
  }
  return out;
}

void PathFollower::SetPath(const std::vector<Point2>& path, std::optional<double> goal_heading) {
  waypoints_ = DensifyPath(path, p_.waypoint_spacing);
  goal_heading_ = goal_heading;
  // waypoints_[0] is where the robot stands; aim at the next one (seed 000, state 6).
  index_ = waypoints_.size() > 1 ? 1 : 0;
  state_ = waypoints_.empty() ? FollowerState::kIdle : external_ ? FollowerState::kDriving : FollowerState::kRotating;
}

void PathFollower::Clear() {
  waypoints_.clear();
  index_ = 0;
  state_ = FollowerState::kIdle;
}

WheelSpeeds PathFollower::Rotate(double dphi) const {
  const double speed = std::clamp(p_.rotate_gain * std::abs(dphi), p_.min_speed, p_.rotate_speed);
  return dphi > 0 ? WheelSpeeds{-speed, speed} : WheelSpeeds{speed, -speed};
}

void PathFollower::SkipReachedWaypoints(const Pose2& pose) {
  // The farthest waypoint already within reach (seed 000's waypoint skipping), e.g. when an
  // avoidance manoeuvre carried the robot past some.
  for (size_t j = waypoints_.size() - 1; j > index_; --j) {
    const double reach = j + 1 == waypoints_.size() ? p_.goal_tolerance : p_.waypoint_radius;
    if (Distance(pose.translation(), waypoints_[j]) <= reach) {
      index_ = j;
      return;
    }
  }
}

void PathFollower::CatchUpWithSteering(const Pose2& pose) {
  // Steered off the path (round people), the robot is level with the waypoint nearest to it; the
  // one after is ahead. The window keeps a path that doubles back from being cut short.
  constexpr size_t kWindow = 60;
  // The search starts one behind the target: the target nearest means level with it, the one
  // before it nearest means not there yet.
  size_t nearest = index_ > 0 ? index_ - 1 : 0;
  double best = Distance(pose.translation(), waypoints_[nearest]);
  for (size_t j = nearest + 1; j < std::min(waypoints_.size(), index_ + kWindow); ++j) {
    const double d = Distance(pose.translation(), waypoints_[j]);
    if (d < best) {
      best = d;
      nearest = j;
    }
  }
  if (nearest >= index_) index_ = std::min(nearest + 1, waypoints_.size() - 1);
}

FollowerCommand PathFollower::Step(const Pose2& pose) {
  if (state_ == FollowerState::kIdle || state_ == FollowerState::kArrived) return {{}, state_};

  SkipReachedWaypoints(pose);
  if (external_ && state_ != FollowerState::kFinalRotation) {
    CatchUpWithSteering(pose);
    state_ = FollowerState::kDriving;
  }
  const bool last = index_ + 1 >= waypoints_.size();
  const Point2 target = waypoints_[index_];
  const double dist = Distance(pose.translation(), target);

  if (state_ == FollowerState::kFinalRotation) {
    const double dphi = NormalizeAngle(*goal_heading_ - pose.theta);
    if (std::abs(dphi) <= p_.goal_heading_tolerance) {
      state_ = FollowerState::kArrived;
      return {{}, state_};
    }
    return {Rotate(dphi), state_};
  }

  // State 9: waypoint reached; next waypoint, or the goal.
  if (dist <= (last ? p_.goal_tolerance : p_.waypoint_radius)) {
    if (!last) {
      ++index_;
      return Step(pose);
    }
    state_ = goal_heading_ ? FollowerState::kFinalRotation : FollowerState::kArrived;
    return Step(pose);
  }

  const double dphi = BearingOf(target, pose);
  // States 7/8 with hysteresis.
  if (state_ == FollowerState::kDriving && std::abs(dphi) > p_.heading_threshold && !external_)
    state_ = FollowerState::kRotating;
  if (state_ == FollowerState::kRotating) {
    if (std::abs(dphi) > p_.heading_resume) return {Rotate(dphi), state_};
    state_ = FollowerState::kDriving;
  }
  double v_nav = p_.v_nav;
  if (last) v_nav = std::clamp(std::sqrt(2.0 * p_.approach_decel * dist), p_.min_speed, p_.v_nav);
  const double dv = p_.k_p * v_nav * dphi;
  return {ClampWheels({v_nav - dv, v_nav + dv}, p_.max_wheel_speed), state_};
}

std::optional<double> PathFollower::SubgoalBearing(const Pose2& pose) const {
  if (state_ != FollowerState::kDriving || index_ >= waypoints_.size()) return std::nullopt;
  return BearingOf(waypoints_[index_], pose);
}

std::vector<Point2> PathFollower::PathAhead(double distance) const {
  if (waypoints_.empty()) return {};
  size_t i = std::min(index_, waypoints_.size() - 1);
  std::vector<Point2> out{waypoints_[i]};
  for (; i + 1 < waypoints_.size() && distance > 0.0; ++i) {
    const double step = Distance(waypoints_[i], waypoints_[i + 1]);
    if (step >= distance) {
      out.emplace_back(waypoints_[i] + (waypoints_[i + 1] - waypoints_[i]) * (distance / std::max(step, 1e-9)));
      break;
    }
    distance -= step;
    out.push_back(waypoints_[i + 1]);
  }
  return out;
}

double PathFollower::DistanceRemaining(const Pose2& pose) const {
  if (waypoints_.empty() || state_ == FollowerState::kIdle) return 0.0;
  double d = Distance(pose.translation(), waypoints_[index_]);
  for (size_t i = index_ + 1; i < waypoints_.size(); ++i) d += Distance(waypoints_[i - 1], waypoints_[i]);
  return d;
}

}  // namespace navd::navigation
