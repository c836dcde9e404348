#include "services/navigation/navigator.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "services/common/error.h"
#include "services/navigation/mission_time_left.h"

namespace navd::navigation {
namespace {
NavigationState FromFollower(FollowerState s) {
  switch (s) {
    case FollowerState::kRotating: return NavigationState::kRotating;
    case FollowerState::kDriving: return NavigationState::kDriving;
    case FollowerState::kFinalRotation: return NavigationState::kFinalRotation;
    default: return NavigationState::kIdle;
  }
}
}  // namespace

void Navigator::BumpLocked() {
  ++status_.sequence;
  changed_.notify_all();
}

uint64_t Navigator::Start(const Mission& mission, const std::vector<Point2>& path, double path_length, double now,
                          bool preempt) {
  if (mission.waypoints.empty()) throw Error(ErrorCode::kInvalidArgument, "waypoints: the mission has none");
  std::lock_guard<std::mutex> lock(mutex_);
  if (status_.active) {
    if (!preempt) {
      throw Error(ErrorCode::kFailedPrecondition,
                  "goal: navigation to " + FormatPoint(status_.goal.pose.translation()) +
                      " is active; rejected the new goal (cancel the active one first, or set preempt)");
    }
    FinishLocked(Outcome::kPreempted, "preempted by a new goal", last_pose_, now);
  }
  mission_ = mission;
  follower_.SetPath(path, mission.waypoints.front().heading());
  status_.goal_id += 1;
  status_.active = true;
  status_.paused = false;
  status_.hold_reason.clear();
  status_.goal = mission.waypoints.front();
  NavigationFeedback& f = status_.feedback;
  f.mission_index = 0;
  f.mission_count = static_cast<uint32_t>(mission.waypoints.size());
  f.laps_completed = 0;
  f.waypoints_reached = 0;
  f.distance_travelled = 0.0;
  odometer_.Start(last_pose_, now);
  started_at_ = now;
  path_length_ = path_length;
  // Without a path the first leg is planned later (the robot starts outside the navigation grid).
  leg_needs_path_ = path.empty();
  f.recoveries = 0;
  f.reflexes = 0;
  progress_.StartMission(follower_.DistanceRemaining(last_pose_), now);
  stale_since_ = -1.0;
  UpdateFeedbackLocked(leg_needs_path_ ? NavigationState::kPlanning : FromFollower(follower_.state()), last_pose_, now);
  BumpLocked();
  return status_.goal_id;
}

bool Navigator::Cancel(uint64_t goal_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!status_.active || (goal_id != 0 && goal_id != status_.goal_id)) return false;
  FinishLocked(Outcome::kCanceled, "cancelled by request", last_pose_, status_.feedback.stamp);
  return true;
}

void Navigator::Pause(double now) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!status_.active) throw Error(ErrorCode::kFailedPrecondition, "pause: no mission is active");
  if (status_.paused) throw Error(ErrorCode::kFailedPrecondition, "pause: the mission is paused already");
  status_.paused = true;
  progress_.Stop(now);
  UpdateFeedbackLocked(NavigationState::kPaused, last_pose_, now);
  BumpLocked();
}

void Navigator::Resume(double now) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!status_.active) throw Error(ErrorCode::kFailedPrecondition, "resume: no mission is active");
  if (!status_.paused) throw Error(ErrorCode::kFailedPrecondition, "resume: the mission is not paused");
  status_.paused = false;
  leg_needs_path_ = true;  // the robot may have been pushed or carried meanwhile
  UpdateFeedbackLocked(NavigationState::kPlanning, last_pose_, now);
  BumpLocked();
}

std::optional<NavigationGoal> Navigator::LegToPlan() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!status_.active || status_.paused || !leg_needs_path_) return std::nullopt;
  return status_.goal;
}

void Navigator::SetLegPath(const std::vector<Point2>& path, double path_length, double now) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!status_.active) return;
  follower_.SetPath(path, status_.goal.heading());
  path_length_ += path_length;
  leg_needs_path_ = false;
  progress_.NewPath(follower_.DistanceRemaining(last_pose_));
  UpdateFeedbackLocked(FromFollower(follower_.state()), last_pose_, now);
  BumpLocked();
}

void Navigator::Abort(const std::string& why, double now) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (status_.active) FinishLocked(Outcome::kFailed, why, last_pose_, now);
}

void Navigator::FinishLocked(Outcome outcome, const std::string& message, const Pose2& pose, double now) {
  NavigationResult r;
  r.outcome = outcome;
  r.message = message;
  r.final_pose = pose;
  r.distance_to_goal = Distance(pose.translation(), status_.goal.pose.translation());
  r.elapsed = now - started_at_;
  r.path_length = path_length_;
  r.distance_travelled = status_.feedback.distance_travelled;
  r.waypoints_reached = status_.feedback.waypoints_reached;
  status_.active = false;
  status_.paused = false;
  status_.hold_reason.clear();
  status_.last_result = r;
  status_.feedback.state = NavigationState::kIdle;
  status_.feedback.eta = 0.0;
  results_.Add(status_.goal_id, r);
  follower_.Clear();
  leg_needs_path_ = false;
  BumpLocked();
}

void Navigator::TrackLocked(const Pose2& pose, double now, bool moving) {
  odometer_.Step(pose, now, moving, status_.active && have_pose_);
  if (status_.active) status_.feedback.distance_travelled = odometer_.distance();
  last_pose_ = pose;
  have_pose_ = true;
}

bool Navigator::AdvanceLocked(const Pose2& pose, double now) {
  NavigationFeedback& f = status_.feedback;
  ++f.waypoints_reached;
  progress_.WaypointReached(now);
  size_t next = f.mission_index + 1;
  if (next >= mission_.waypoints.size()) {
    const bool another_lap = mission_.cyclic && (mission_.laps == 0 || f.laps_completed + 1 < mission_.laps);
    if (!another_lap) {
      if (mission_.cyclic) ++f.laps_completed;
      const std::string msg = mission_.waypoints.size() == 1
                                  ? "goal reached"
                                  : "mission complete: reached " + std::to_string(f.waypoints_reached) + " waypoints";
      FinishLocked(Outcome::kSucceeded, msg, pose, now);
      return false;
    }
    ++f.laps_completed;
    next = 0;
  }
  f.mission_index = static_cast<uint32_t>(next);
  status_.goal = mission_.waypoints[next];
  follower_.Clear();
  leg_needs_path_ = true;
  return true;
}

void Navigator::UpdateFeedbackLocked(NavigationState state, const Pose2& pose, double now) {
  NavigationFeedback& f = status_.feedback;
  f.state = state;
  f.pose = pose;
  f.stamp = now;
  const bool following = !leg_needs_path_ && follower_.state() != FollowerState::kIdle;
  f.distance_remaining =
      following ? follower_.DistanceRemaining(pose) : Distance(pose.translation(), status_.goal.pose.translation());
  f.waypoint_index = static_cast<uint32_t>(follower_.waypoint_index());
  f.waypoint_count = static_cast<uint32_t>(follower_.waypoint_count());
  if (!status_.active) {
    f.eta = 0.0;
    return;
  }
  f.eta = MissionTimeLeft(mission_, f, odometer_.moving_time(), options_.follower.v_nav);
}

WheelSpeeds Navigator::Step(const Pose2& pose, double now, bool sensors_fresh) {
  std::lock_guard<std::mutex> lock(mutex_);
  const bool stale_changed = status_.sensors_stale == sensors_fresh;
  status_.sensors_stale = !sensors_fresh;
  if (!status_.active) {
    TrackLocked(pose, now, false);
    status_.feedback.pose = pose;
    status_.feedback.stamp = now;
    if (stale_changed) BumpLocked();
    return {};
  }
  if (status_.paused) {
    TrackLocked(pose, now, false);
    UpdateFeedbackLocked(NavigationState::kPaused, pose, now);
    BumpLocked();
    return {};
  }
  if (!sensors_fresh) {
    WaitForSensorsLocked(pose, now);
    return {};
  }
  stale_since_ = -1.0;
  status_.hold_reason.clear();
  progress_.Drive(now);  // time spent stopped is not a lack of progress
  TrackLocked(pose, now, true);
  if (mission_.max_distance > 0.0 && status_.feedback.distance_travelled >= mission_.max_distance) {
    char msg[96];
    std::snprintf(msg, sizeof msg, "travelled %.1f m, the mission's max_distance", status_.feedback.distance_travelled);
    FinishLocked(Outcome::kSucceeded, msg, pose, now);
    return {};
  }
  if (leg_needs_path_) {  // the executive plans it before the next step
    UpdateFeedbackLocked(NavigationState::kPlanning, pose, now);
    BumpLocked();
    return {};
  }
  const FollowerCommand cmd = follower_.Step(pose);
  if (cmd.state == FollowerState::kArrived) {
    if (AdvanceLocked(pose, now)) {
      UpdateFeedbackLocked(NavigationState::kPlanning, pose, now);
      BumpLocked();
    }
    return {};
  }
  UpdateFeedbackLocked(FromFollower(cmd.state), pose, now);
  if (!CheckProgressLocked(cmd.state, pose, now)) return {};
  BumpLocked();
  return cmd.wheels;
}

void Navigator::WaitForSensorsLocked(const Pose2& pose, double now) {
  TrackLocked(pose, now, false);
  progress_.Stop(now);
  if (stale_since_ < 0) stale_since_ = now;
  if (now - stale_since_ > options_.stale_timeout) {
    char msg[64];
    std::snprintf(msg, sizeof msg, "sensors stale for more than %.1f s", options_.stale_timeout);
    FinishLocked(Outcome::kFailed, msg, pose, now);
    return;
  }
  status_.hold_reason = "sensors stale";
  UpdateFeedbackLocked(NavigationState::kStoppedStaleSensors, pose, now);
  BumpLocked();
}

bool Navigator::CheckProgressLocked(FollowerState state, const Pose2& pose, double now) {
  if (progress_.Progressed(status_.feedback.distance_remaining, state == FollowerState::kFinalRotation, now))
    return true;
  char why[96];
  std::snprintf(why, sizeof why, "no progress for %.0f s (%.2f m still to go)", options_.progress_timeout,
                status_.feedback.distance_remaining);
  // The progress clock starts again after the recovery.
  if (RecoverOrFailLocked(why, "the robot seems stuck", pose, now)) progress_.RestartClock(now);
  return false;
}

void Navigator::NoteContact(const Point2& where, double now) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!status_.active) return;
  const int here = progress_.Contact(where);
  if (here < options_.max_contacts) return;
  char why[96];
  std::snprintf(why, sizeof why, "bumped into something at (%.2f, %.2f) %d times", where.x(), where.y(), here);
  if (RecoverOrFailLocked(why, "the way seems blocked", last_pose_, now)) progress_.ForgetContacts();
}

bool Navigator::RecoverOrFailLocked(const std::string& why, const std::string& verdict, const Pose2& pose, double now) {
  if (progress_.AllowRecovery(pose.translation())) {
    ++status_.feedback.recoveries;  // the executive runs the recovery
    BumpLocked();
    return true;
  }
  char where[64];
  std::snprintf(where, sizeof where, " within %.1f m of here", options_.recovery_radius);
  FinishLocked(
      Outcome::kFailed,
      why + " after " + std::to_string(options_.max_recoveries) + " recoveries on this leg" + where + ": " + verdict,
      pose, now);
  return false;
}

void Navigator::Hold(const Pose2& pose, double now, NavigationState state, const std::string& reason,
                     bool sensors_fresh) {
  std::lock_guard<std::mutex> lock(mutex_);
  TrackLocked(pose, now, false);
  if (status_.sensors_stale == sensors_fresh) {
    status_.sensors_stale = !sensors_fresh;
    BumpLocked();
  }
  if (!status_.active) return;
  progress_.Stop(now);
  status_.hold_reason = reason;
  if (!status_.paused) leg_needs_path_ = true;
  UpdateFeedbackLocked(status_.paused ? NavigationState::kPaused : state, pose, now);
  BumpLocked();
}

void Navigator::SetBehaviour(const std::string& behaviour, std::vector<ProcessUtility> utilities) {
  std::lock_guard<std::mutex> lock(mutex_);
  status_.feedback.behaviour = behaviour;
  status_.feedback.utilities = std::move(utilities);
}

bool Navigator::ReplanIfBlocked(const std::function<bool(const Point2&)>& blocked, double ahead) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!status_.active || status_.paused || leg_needs_path_) return false;
  const std::vector<Point2>& path = follower_.waypoints();
  const size_t from = follower_.waypoint_index();
  if (from >= path.size()) return false;
  Point2 previous = last_pose_.translation();
  double along = 0.0;
  for (size_t i = from; i < path.size() && along <= ahead; ++i) {
    // The waypoints are at most d_wp apart: checking them is checking the path.
    along += Distance(previous, path[i]);
    previous = path[i];
    if (blocked(path[i])) {
      leg_needs_path_ = true;
      BumpLocked();
      return true;
    }
  }
  return false;
}

void Navigator::SetMovingObstacles(double danger, std::vector<planning::MovingBody> obstacles) {
  std::lock_guard<std::mutex> lock(mutex_);
  status_.feedback.danger = danger;
  status_.feedback.moving_obstacles = std::move(obstacles);
}

bool Navigator::TakeStuck() {
  std::lock_guard<std::mutex> lock(mutex_);
  const bool due = progress_.TakeRecovery();
  return due && status_.active;
}

void Navigator::SetSpeedLimit(double limit) {
  std::lock_guard<std::mutex> lock(mutex_);
  status_.feedback.speed_limit = limit;
}

void Navigator::SetReflex(const std::string& reflex) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (reflex == status_.feedback.reflex) return;
  if (status_.feedback.reflex.empty() && status_.active) ++status_.feedback.reflexes;
  status_.feedback.reflex = reflex;
  BumpLocked();
}

std::optional<double> Navigator::SubgoalBearing(const Pose2& pose) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return follower_.SubgoalBearing(pose);
}

void Navigator::SetExternalSteering(bool on) {
  std::lock_guard<std::mutex> lock(mutex_);
  follower_.SetExternalSteering(on);
}

std::vector<Point2> Navigator::PathAhead(double distance) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!status_.active) return {};
  return follower_.PathAhead(distance);
}

std::vector<Point2> Navigator::LegPath() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!status_.active) return {};
  return follower_.waypoints();
}

std::vector<NavigationGoal> Navigator::MissionWaypoints() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!status_.active) return {};
  return mission_.waypoints;
}

NavigationStatus Navigator::Status() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return status_;
}

std::optional<NavigationResult> Navigator::ResultOf(uint64_t goal_id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return results_.Find(goal_id);
}

uint64_t Navigator::WaitForChange(uint64_t seen, double timeout_s) const {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] { return status_.sequence != seen; });
  return status_.sequence;
}

}  // namespace navd::navigation
