#pragma once
// The navigation executive, first version: one goal at a time, followed with PathFollower, with
// the life cycle clients see (active -> succeeded / failed / cancelled / preempted), stale-sensor
// stops, and a change counter that streaming handlers wait on. Thread-safe: the control loop
// calls Step, gRPC handlers call the rest. Map frame, metres, radians, seconds of the daemon clock.
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "services/common/diff_drive.h"
#include "services/common/pose2.h"
#include "services/navigation/path_follower.h"

namespace navd::navigation {

// Mirrors navd.v1.NavigationState.
enum class NavigationState { kIdle = 1, kRotating = 2, kDriving = 3, kFinalRotation = 4, kStoppedStaleSensors = 5 };
// Mirrors navd.v1.Outcome.
enum class Outcome { kNone = 0, kSucceeded = 1, kFailed = 2, kCanceled = 3, kPreempted = 4 };

struct NavigationGoal {
  Pose2 pose;
  bool use_heading = false;
};

struct NavigationResult {
  Outcome outcome = Outcome::kNone;
  std::string message;
  Pose2 final_pose;
  double distance_to_goal = 0.0;
  double elapsed = 0.0;
  double path_length = 0.0;
};

struct NavigationFeedback {
  NavigationState state = NavigationState::kIdle;
  Pose2 pose;
  double distance_remaining = 0.0;
  uint32_t waypoint_index = 0;
  uint32_t waypoint_count = 0;
  double stamp = 0.0;
};

struct NavigationStatus {
  uint64_t goal_id = 0;          // id of the active or last goal; 0 before the first
  bool active = false;
  bool sensors_stale = false;
  NavigationGoal goal;
  NavigationFeedback feedback;
  std::optional<NavigationResult> last_result;
  uint64_t sequence = 0;         // increments on every change
};

struct NavigatorOptions {
  PathFollowerParams follower;
  // A goal fails when the distance left has not shrunk by progress_distance for progress_timeout
  // seconds (the robot is stuck, e.g. pushing against an unmapped obstacle)...
  double progress_timeout = 30.0;   // s
  double progress_distance = 0.05;  // m
  // ...or when sensors stayed stale this long.
  double stale_timeout = 10.0;      // s
};

class Navigator {
 public:
  explicit Navigator(const NavigatorOptions& options = {}) : options_(options), follower_(options.follower) {}

  // Starts following `path` (start first) to `goal`. When a goal is active: throws
  // navd::Error(kFailedPrecondition) unless preempt, in which case the old goal ends PREEMPTED.
  // Returns the new goal's id.
  uint64_t Start(const NavigationGoal& goal, const std::vector<Point2>& path, double path_length, double now,
                 bool preempt);
  // Cancels the active goal (any goal when goal_id is 0). Returns whether one was cancelled.
  bool Cancel(uint64_t goal_id = 0);
  // One control step: returns the wheel command. sensors_fresh=false stops the robot and holds
  // the goal until sensors return.
  WheelSpeeds Step(const Pose2& pose, double now, bool sensors_fresh);

  NavigationStatus Status() const;
  // The result of goal `goal_id` once it has ended.
  std::optional<NavigationResult> ResultOf(uint64_t goal_id) const;
  // Blocks until the status sequence passes `seen` or `timeout_s` elapses; returns the sequence.
  uint64_t WaitForChange(uint64_t seen, double timeout_s) const;

 private:
  void FinishLocked(Outcome outcome, const std::string& message, const Pose2& pose, double now);
  void BumpLocked();

  NavigatorOptions options_;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  PathFollower follower_;
  double best_remaining_ = 0.0;     // smallest distance left so far (progress check)
  double best_remaining_at_ = 0.0;  // when it was reached
  double stale_since_ = -1.0;       // when sensors went stale; < 0 while fresh
  NavigationStatus status_;
  std::vector<std::pair<uint64_t, NavigationResult>> results_;  // recent results by goal id
  double started_at_ = 0.0;
  double path_length_ = 0.0;
  Pose2 last_pose_;
};

const char* NavigationStateName(NavigationState s);
const char* OutcomeName(Outcome o);

}  // namespace navd::navigation
