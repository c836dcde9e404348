#include "services/navigation/navigator.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "services/common/error.h"

namespace navd::navigation {
namespace {
constexpr size_t kResultsKept = 64;

// How many of `places` lie within `radius` (m) of `at`: bumps and recoveries are counted by place.
int CountWithin(const std::vector<Point2>& places, const Point2& at, double radius) {
  int n = 0;
  for (const Point2& p : places) n += Distance(p, at) <= radius;
  return n;
}

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
    case NavigationState::kPaused: return "paused";
    case NavigationState::kEmergencyStop: return "emergency_stop";
    case NavigationState::kPlanning: return "planning";
    case NavigationState::kAvoiding: return "avoiding";
    case NavigationState::kRecovering: return "recovering";
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

namespace {
std::optional<double> HeadingOf(const NavigationGoal& g) {
  return g.use_heading ? std::optional<double>(g.pose.theta) : std::nullopt;
}
// A pose estimate that jumps farther than this in one control step was re-anchored (set-pose,
// relocalisation); the jump is not distance the robot travelled.
constexpr double kMaxStepTravel = 0.5;   // m
constexpr double kOdometerChord = 0.05;  // m
}  // namespace

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
  follower_.SetPath(path, HeadingOf(mission.waypoints.front()));
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
  odometer_anchor_ = last_pose_.translation();
  started_at_ = now;
  moving_time_ = 0.0;
  last_step_ = now;
  path_length_ = path_length;
  // Without a path the first leg is planned later (the robot starts outside the navigation grid).
  leg_needs_path_ = path.empty();
  stuck_ = false;
  f.recoveries = 0;
  f.reflexes = 0;
  leg_recoveries_.clear();
  leg_contacts_.clear();
  best_remaining_ = follower_.DistanceRemaining(last_pose_);
  best_remaining_at_ = now;
  stale_since_ = held_since_ = -1.0;
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
  StopProgressClockLocked(now);
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
  follower_.SetPath(path, HeadingOf(status_.goal));
  path_length_ += path_length;
  leg_needs_path_ = false;
  // A new path restarts the distance measured, not the clock: the clock starts with the leg (and
  // again after a recovery). A leg replanned every second because an obstacle too near to plan
  // round lies across its path, while the scan guard holds the robot, would otherwise never be
  // called stuck (an office run stood 1000 s so).
  best_remaining_ = follower_.DistanceRemaining(last_pose_);
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
  results_.emplace_back(status_.goal_id, r);
  if (results_.size() > kResultsKept) results_.erase(results_.begin());
  follower_.Clear();
  leg_needs_path_ = false;
  BumpLocked();
}

void Navigator::TrackLocked(const Pose2& pose, double now, bool moving) {
  if (status_.active && have_pose_) {
    // Distance is booked in chords of at least kOdometerChord: summing every control step's
    // displacement would also sum the estimate's millimetre jitter (about 1 % over 100 m).
    const double step = Distance(pose.translation(), odometer_anchor_);
    if (step >= kMaxStepTravel) {
      odometer_anchor_ = pose.translation();  // a re-anchored estimate, not travel
    } else if (step >= kOdometerChord) {
      status_.feedback.distance_travelled += step;
      odometer_anchor_ = pose.translation();
    }
    if (moving && last_step_ >= 0.0 && now > last_step_) moving_time_ += now - last_step_;
  } else {
    odometer_anchor_ = pose.translation();
  }
  last_step_ = now;
  last_pose_ = pose;
  have_pose_ = true;
}

void Navigator::StopProgressClockLocked(double now) {
  if (held_since_ < 0.0) held_since_ = now;
}

bool Navigator::AdvanceLocked(const Pose2& pose, double now) {
  NavigationFeedback& f = status_.feedback;
  ++f.waypoints_reached;
  leg_recoveries_.clear();
  leg_contacts_.clear();
  size_t next = f.mission_index + 1;
  if (next >= mission_.waypoints.size()) {
    const bool another_lap = mission_.cyclic && (mission_.laps == 0 || f.laps_completed + 1 < mission_.laps);
    if (!another_lap) {
      if (mission_.cyclic) ++f.laps_completed;
      char msg[96];
      if (mission_.waypoints.size() == 1) {
        std::snprintf(msg, sizeof msg, "goal reached");
      } else {
        std::snprintf(msg, sizeof msg, "mission complete: reached %u waypoints", f.waypoints_reached);
      }
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
  best_remaining_at_ = now;  // the progress clock of the new leg
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
  // Distance left: this leg's path, then straight lines through the remaining waypoints (to the
  // mission's end, or to the lap's end when it repeats without end).
  const auto& w = mission_.waypoints;
  const auto leg = [&](size_t j) { return Distance(w[j - 1].pose.translation(), w[j].pose.translation()); };
  double rest = f.distance_remaining;
  for (size_t j = f.mission_index + 1; j < w.size(); ++j) rest += leg(j);
  if (mission_.cyclic && mission_.laps > 0 && f.laps_completed + 1 < mission_.laps) {
    double lap = Distance(w.back().pose.translation(), w.front().pose.translation());
    for (size_t j = 1; j < w.size(); ++j) lap += leg(j);
    rest += lap * (mission_.laps - f.laps_completed - 1);
  }
  if (mission_.max_distance > 0.0) {
    const double left = std::max(0.0, mission_.max_distance - f.distance_travelled);
    rest = mission_.cyclic && mission_.laps == 0 ? left : std::min(rest, left);
  }
  // The mission's own average speed once it has one; before that, a guess from the cruise speed.
  const double speed =
      moving_time_ > 5.0 ? std::max(0.05, f.distance_travelled / moving_time_) : 0.6 * options_.follower.v_nav;
  f.eta = rest / speed;
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
    TrackLocked(pose, now, false);
    StopProgressClockLocked(now);
    if (stale_since_ < 0) stale_since_ = now;
    if (now - stale_since_ > options_.stale_timeout) {
      char msg[64];
      std::snprintf(msg, sizeof msg, "sensors stale for more than %.1f s", options_.stale_timeout);
      FinishLocked(Outcome::kFailed, msg, pose, now);
      return {};
    }
    status_.hold_reason = "sensors stale";
    UpdateFeedbackLocked(NavigationState::kStoppedStaleSensors, pose, now);
    BumpLocked();
    return {};
  }
  stale_since_ = -1.0;
  status_.hold_reason.clear();
  if (held_since_ >= 0.0) {
    // Time spent stopped (stale sensors, pause, another behaviour) is not a lack of progress.
    best_remaining_at_ += now - held_since_;
    held_since_ = -1.0;
  }
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
  if (status_.feedback.distance_remaining < best_remaining_ - options_.progress_distance ||
      cmd.state == FollowerState::kFinalRotation) {
    best_remaining_ = status_.feedback.distance_remaining;
    best_remaining_at_ = now;
  } else if (now - best_remaining_at_ > options_.progress_timeout) {
    char why[96];
    std::snprintf(why, sizeof why, "no progress for %.0f s (%.2f m still to go)", options_.progress_timeout,
                  status_.feedback.distance_remaining);
    // The progress clock starts again after the recovery.
    if (RecoverOrFailLocked(why, "the robot seems stuck", pose, now)) best_remaining_at_ = now;
    return {};
  }
  BumpLocked();
  return cmd.wheels;
}

void Navigator::NoteContact(const Point2& where, double now) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!status_.active) return;
  leg_contacts_.push_back(where);
  const int here = CountWithin(leg_contacts_, where, options_.contact_radius);
  if (here < options_.max_contacts) return;
  char why[96];
  std::snprintf(why, sizeof why, "bumped into something at (%.2f, %.2f) %d times", where.x(), where.y(), here);
  if (RecoverOrFailLocked(why, "the way seems blocked", last_pose_, now)) leg_contacts_.clear();
}

bool Navigator::RecoverOrFailLocked(const std::string& why, const std::string& verdict, const Pose2& pose, double now) {
  if (CountWithin(leg_recoveries_, pose.translation(), options_.recovery_radius) < options_.max_recoveries) {
    leg_recoveries_.push_back(pose.translation());
    ++status_.feedback.recoveries;
    stuck_ = true;  // the executive runs the recovery
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
  StopProgressClockLocked(now);
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
  const bool stuck = stuck_ && status_.active;
  stuck_ = false;
  return stuck;
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
