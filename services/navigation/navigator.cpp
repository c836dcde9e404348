#include "services/navigation/navigator.h"

#include <chrono>
#include <cstdio>

#include "services/common/error.h"

namespace navd::navigation {
namespace {
constexpr size_t kResultsKept = 64;

NavigationState FromFollower(FollowerState s) {
  switch (s) {
    case FollowerState::kRotating: return NavigationState::kRotating;
    case FollowerState::kDriving: return NavigationState::kDriving;
    case FollowerState::kFinalRotation: return NavigationState::kFinalRotation;
    default: return NavigationState::kIdle;
  }
}
}  // namespace

const char* NavigationStateName(NavigationState s) {
  switch (s) {
    case NavigationState::kIdle: return "idle";
    case NavigationState::kRotating: return "rotating";
    case NavigationState::kDriving: return "driving";
    case NavigationState::kFinalRotation: return "final_rotation";
    case NavigationState::kStoppedStaleSensors: return "stopped_stale_sensors";
  }
  return "unknown";
}

const char* OutcomeName(Outcome o) {
  switch (o) {
    case Outcome::kNone: return "none";
    case Outcome::kSucceeded: return "succeeded";
    case Outcome::kFailed: return "failed";
    case Outcome::kCanceled: return "canceled";
    case Outcome::kPreempted: return "preempted";
  }
  return "unknown";
}

void Navigator::BumpLocked() {
  ++status_.sequence;
  changed_.notify_all();
}

uint64_t Navigator::Start(const NavigationGoal& goal, const std::vector<Point2>& path, double path_length,
                          double now, bool preempt) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (status_.active) {
    if (!preempt) {
      throw Error(ErrorCode::kFailedPrecondition,
                  "goal: navigation to " + FormatPoint(status_.goal.pose.translation()) +
                      " is active; rejected the new goal (cancel the active one first, or set preempt)");
    }
    FinishLocked(Outcome::kPreempted, "preempted by a new goal", last_pose_, now);
  }
  follower_.SetPath(path, goal.use_heading ? std::optional<double>(goal.pose.theta) : std::nullopt);
  status_.goal_id += 1;
  status_.active = true;
  status_.goal = goal;
  status_.feedback = {FromFollower(follower_.state()), last_pose_, follower_.DistanceRemaining(last_pose_),
                      static_cast<uint32_t>(follower_.waypoint_index()),
                      static_cast<uint32_t>(follower_.waypoint_count()), now};
  started_at_ = now;
  path_length_ = path_length;
  best_remaining_ = status_.feedback.distance_remaining;
  best_remaining_at_ = now;
  stale_since_ = -1.0;
  BumpLocked();
  return status_.goal_id;
}

bool Navigator::Cancel(uint64_t goal_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!status_.active || (goal_id != 0 && goal_id != status_.goal_id)) return false;
  FinishLocked(Outcome::kCanceled, "cancelled by request", last_pose_, status_.feedback.stamp);
  return true;
}

void Navigator::FinishLocked(Outcome outcome, const std::string& message, const Pose2& pose, double now) {
  NavigationResult r;
  r.outcome = outcome;
  r.message = message;
  r.final_pose = pose;
  r.distance_to_goal = Distance(pose.translation(), status_.goal.pose.translation());
  r.elapsed = now - started_at_;
  r.path_length = path_length_;
  status_.active = false;
  status_.last_result = r;
  status_.feedback.state = NavigationState::kIdle;
  results_.emplace_back(status_.goal_id, r);
  if (results_.size() > kResultsKept) results_.erase(results_.begin());
  follower_.Clear();
  BumpLocked();
}

WheelSpeeds Navigator::Step(const Pose2& pose, double now, bool sensors_fresh) {
  std::lock_guard<std::mutex> lock(mutex_);
  last_pose_ = pose;
  const bool stale_changed = status_.sensors_stale == sensors_fresh;
  status_.sensors_stale = !sensors_fresh;
  if (!status_.active) {
    status_.feedback.pose = pose;
    status_.feedback.stamp = now;
    if (stale_changed) BumpLocked();
    return {};
  }
  if (!sensors_fresh) {
    if (stale_since_ < 0) stale_since_ = now;
    if (now - stale_since_ > options_.stale_timeout) {
      char msg[64];
      std::snprintf(msg, sizeof msg, "sensors stale for more than %.1f s", options_.stale_timeout);
      FinishLocked(Outcome::kFailed, msg, pose, now);
      return {};
    }
    status_.feedback.state = NavigationState::kStoppedStaleSensors;
    status_.feedback.stamp = now;
    BumpLocked();
    return {};
  }
  if (stale_since_ >= 0) {
    // Time spent stopped for stale sensors is not the robot's lack of progress.
    best_remaining_at_ += now - stale_since_;
    stale_since_ = -1.0;
  }
  const FollowerCommand cmd = follower_.Step(pose);
  if (cmd.state == FollowerState::kArrived) {
    FinishLocked(Outcome::kSucceeded, "goal reached", pose, now);
    return {};
  }
  status_.feedback = {FromFollower(cmd.state), pose, follower_.DistanceRemaining(pose),
                      static_cast<uint32_t>(follower_.waypoint_index()),
                      static_cast<uint32_t>(follower_.waypoint_count()), now};
  if (status_.feedback.distance_remaining < best_remaining_ - options_.progress_distance ||
      cmd.state == FollowerState::kFinalRotation) {
    best_remaining_ = status_.feedback.distance_remaining;
    best_remaining_at_ = now;
  } else if (now - best_remaining_at_ > options_.progress_timeout) {
    char msg[96];
    std::snprintf(msg, sizeof msg, "no progress for %.0f s (%.2f m still to go): the robot seems stuck",
                  options_.progress_timeout, status_.feedback.distance_remaining);
    FinishLocked(Outcome::kFailed, msg, pose, now);
    return {};
  }
  BumpLocked();
  return cmd.wheels;
}

NavigationStatus Navigator::Status() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return status_;
}

std::optional<NavigationResult> Navigator::ResultOf(uint64_t goal_id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [id, r] : results_)
    if (id == goal_id) return r;
  return std::nullopt;
}

uint64_t Navigator::WaitForChange(uint64_t seen, double timeout_s) const {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] { return status_.sequence != seen; });
  return status_.sequence;
}

}  // namespace navd::navigation
