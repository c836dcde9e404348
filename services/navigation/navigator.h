#pragma once
// The navigator: runs one mission at a time (a goal, or waypoints in order, optionally cyclic),
// leg by leg with PathFollower, with the life cycle clients see (active -> succeeded / failed /
// cancelled / preempted), pause and resume, holds while another motor behaviour has the robot,
// stale-sensor stops, progress feedback (distance left, distance travelled, ETA) and a change
// counter that streaming handlers wait on. It does not plan: when a leg needs a path it says so
// (LegToPlan) and the executive plans it. Thread-safe: the control loop calls Step/Hold and the
// leg functions, gRPC handlers the rest. Map frame, metres, radians, seconds of the daemon clock.
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "services/common/diff_drive.h"
#include "services/common/pose2.h"
#include "services/navigation/grid_reentry.h"
#include "services/navigation/leg_progress.h"
#include "services/navigation/mission_odometer.h"
#include "services/navigation/navigation_status.h"
#include "services/navigation/path_follower.h"
#include "services/navigation/sonar_reflex.h"
#include "services/navigation/utility_decision_maker.h"
#include "services/planning/global_planner.h"

namespace navd::navigation {

// What the executive does when the robot is stuck, as Nav2's recovery behaviours, in turn: forget
// the tracked obstacles and replan (Nav2's clear costmap), back up, spin in place (the laser sees
// the whole surroundings, the localiser too), wait (what blocks may move on); then the leg is
// replanned from where the robot stands.
struct RecoveryOptions {
  double back_up_distance = 0.15;  // m, when the rear is free that far
  double back_up_speed = 0.10;     // m/s
  double spin_angle = 1.57;        // rad
  double spin_rate = 0.5;          // rad/s
  double wait_time = 5.0;          // s
};

struct NavigatorOptions {
  PathFollowerParams follower;
  // The robot is stuck when the distance left on a leg has not shrunk by progress_distance for
  // progress_timeout seconds of driving (e.g. pushing against an unmapped obstacle): a recovery
  // runs, up to max_recoveries within recovery_radius of one place on a leg (to the next
  // waypoint); stuck there once more, the mission fails. Recoveries that freed the robot further
  // back do not count: an office leg past two panes of glass spent its three on the first and
  // then gave up at the second, 5 m on...
  double recovery_radius = 1.0;     // m
  double progress_timeout = 15.0;   // s
  double progress_distance = 0.05;  // m
  int max_recoveries = 3;
  // ...or when a bumper is pressed this many times within contact_radius of one place on a leg
  // (drive, bump, back away, replan, drive into it again: sooner than the progress clock, which
  // stands still while the bumper holds the robot). Replans do not restart that clock; a new leg
  // and a recovery do.
  int max_contacts = 3;
  double contact_radius = 0.3;  // m
  RecoveryOptions recovery;
  // Seed 000's way back onto the navigation grid when a leg cannot start where the robot is.
  GridReentryOptions reentry;
  // Seed 004's reflexes on the sonar ring, summed with the path follower's command.
  SonarReflexOptions reflex;
  // ...or when sensors stayed stale this long.
  double stale_timeout = 10.0;  // s
};

class Navigator {
 public:
  explicit Navigator(const NavigatorOptions& options = {})
      : options_(options),
        follower_(options.follower),
        progress_(LegProgressOptions{options.progress_distance, options.progress_timeout, options.recovery_radius,
                                     options.max_recoveries, options.contact_radius, options.max_contacts}) {}

  // Starts `mission` with `path` (start first) for its first leg. When a mission is active: throws
  // navd::Error(kFailedPrecondition) unless preempt, in which case the old one ends PREEMPTED.
  // Returns the new mission's id.
  uint64_t Start(const Mission& mission, const std::vector<Point2>& path, double path_length, double now, bool preempt);
  uint64_t Start(const NavigationGoal& goal, const std::vector<Point2>& path, double path_length, double now,
                 bool preempt) {
    return Start(Mission{{goal}}, path, path_length, now, preempt);
  }
  // Cancels the active mission (any when goal_id is 0). Returns whether one was cancelled.
  bool Cancel(uint64_t goal_id = 0);
  // Pause stops the robot and keeps the mission; Resume replans from where the robot is then.
  // Both throw navd::Error(kFailedPrecondition) with no active mission, or when already
  // paused / not paused.
  void Pause(double now);
  void Resume(double now);

  // The waypoint whose leg needs a path now (after a leg, a resume or a hold), if any.
  std::optional<NavigationGoal> LegToPlan() const;
  void SetLegPath(const std::vector<Point2>& path, double path_length, double now);
  // Ends the active mission FAILED (e.g. no path to its next waypoint).
  void Abort(const std::string& why, double now);

  // One control step of the navigation behaviour: returns the wheel command. sensors_fresh=false
  // stops the robot and holds the mission until sensors return.
  WheelSpeeds Step(const Pose2& pose, double now, bool sensors_fresh);
  // Another motor behaviour has the robot this step (state says which kind); the progress clock
  // stops, and the leg is replanned when navigation gets the robot back.
  void Hold(const Pose2& pose, double now, NavigationState state, const std::string& reason, bool sensors_fresh);
  // The decision maker's standing, carried in the feedback.
  void SetBehaviour(const std::string& behaviour, std::vector<ProcessUtility> utilities);
  // Replans the current leg when a point of the rest of its path within `ahead` metres of the
  // robot is `blocked` (map frame, metres); returns whether it asked for a new path.
  bool ReplanIfBlocked(const std::function<bool(const Point2&)>& blocked, double ahead);
  // What the moving-obstacle detection sees, carried in the feedback.
  void SetMovingObstacles(double danger, std::vector<planning::MovingBody> obstacles);
  // Whether the robot got stuck since the last call (a recovery is due; the feedback counts them).
  bool TakeStuck();
  // A bumper was pressed at `where` (map frame): repeated contacts at one place make the robot stuck.
  void NoteContact(const Point2& where, double now);
  // The speed zones' limit at the robot (m/s; 0: none), carried in the feedback.
  void SetSpeedLimit(double limit);
  // What the sonar reflex does now (empty: nothing), carried in the feedback; counts its onsets.
  void SetReflex(const std::string& reflex);
  // Bearing (rad, robot frame) of the path point the follower steers to, while it drives forward:
  // seed 004's navigator vector. nullopt otherwise.
  std::optional<double> SubgoalBearing(const Pose2& pose) const;
  // Another controller steers the robot along the leg (PathFollower::SetExternalSteering).
  void SetExternalSteering(bool on);
  // The leg's path ahead of the robot for `distance` metres, while a leg is driven; else empty.
  std::vector<Point2> PathAhead(double distance) const;
  // The current leg's whole path as planned (densified), while a mission is active; else empty.
  std::vector<Point2> LegPath() const;
  // The active mission's waypoints; empty without one.
  std::vector<NavigationGoal> MissionWaypoints() const;

  NavigationStatus Status() const;
  // The result of mission `goal_id` once it has ended.
  std::optional<NavigationResult> ResultOf(uint64_t goal_id) const;
  // Blocks until the status sequence passes `seen` or `timeout_s` elapses; returns the sequence.
  uint64_t WaitForChange(uint64_t seen, double timeout_s) const;
  const NavigatorOptions& options() const { return options_; }

 private:
  void FinishLocked(Outcome outcome, const std::string& message, const Pose2& pose, double now);
  void BumpLocked();
  // Books the robot's motion to `pose` and the time since the last step.
  void TrackLocked(const Pose2& pose, double now, bool moving);
  // The current leg is done: next waypoint, next lap, or the end. Returns false when it ended.
  bool AdvanceLocked(const Pose2& pose, double now);
  void UpdateFeedbackLocked(NavigationState state, const Pose2& pose, double now);
  // A step with stale sensors: the robot stands, and the mission fails after stale_timeout.
  void WaitForSensorsLocked(const Pose2& pose, double now);
  // Whether the leg progressed (distance remaining down by progress_distance) within
  // progress_timeout; when not, a recovery is due or the mission fails (false).
  bool CheckProgressLocked(FollowerState state, const Pose2& pose, double now);
  // The robot is stuck on this leg: a recovery is due (true), or, when they are spent, the
  // mission fails: "<why> after N recoveries on this leg: <verdict>".
  bool RecoverOrFailLocked(const std::string& why, const std::string& verdict, const Pose2& pose, double now);

  NavigatorOptions options_;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  PathFollower follower_;
  Mission mission_;
  bool leg_needs_path_ = false;
  LegProgress progress_;
  double stale_since_ = -1.0;  // when sensors went stale; < 0 while fresh
  NavigationStatus status_;
  RecentResults results_;
  double started_at_ = 0.0;
  MissionOdometer odometer_;
  double path_length_ = 0.0;
  Pose2 last_pose_;
  bool have_pose_ = false;
};

}  // namespace navd::navigation
