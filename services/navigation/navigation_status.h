#pragma once
// What navd's navigation reports: the state of a mission (NavigationStatus, with its feedback each
// control step and its result at the end), as the gRPC API mirrors it. Map frame, metres, seconds.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "services/common/pose2.h"
#include "services/navigation/utility_decision_maker.h"
#include "services/planning/global_planner.h"

namespace navd::navigation {

// Mirrors navd.v1.NavigationState.
enum class NavigationState {
  kIdle = 1,
  kRotating = 2,
  kDriving = 3,
  kFinalRotation = 4,
  kStoppedStaleSensors = 5,
  kPaused = 6,
  kEmergencyStop = 7,  // held by the emergency-stop behaviour (contact, lost pose)
  kPlanning = 8,       // between legs, or replanning after a hold or resume
  kAvoiding = 9,       // the moving-obstacle avoidance behaviour has the robot
  kRecovering = 10,    // stuck: a recovery runs before the leg is replanned
};
// Mirrors navd.v1.Outcome.
enum class Outcome { kNone = 0, kSucceeded = 1, kFailed = 2, kCanceled = 3, kPreempted = 4 };

struct NavigationGoal {
  Pose2 pose;
  bool use_heading = false;
  // The heading to end the leg with, when the goal has one.
  std::optional<double> heading() const { return use_heading ? std::optional<double>(pose.theta) : std::nullopt; }
};

// Waypoints visited in order. A single waypoint is a NavigateTo goal.
struct Mission {
  std::vector<NavigationGoal> waypoints;
  bool cyclic = false;        // after the last waypoint, start over at the first
  uint32_t laps = 0;          // with cyclic: end after this many laps; 0 = until cancelled
  double max_distance = 0.0;  // m: end (succeeded) after travelling this far; 0 = no limit
};

struct NavigationResult {
  Outcome outcome = Outcome::kNone;
  std::string message;
  Pose2 final_pose;
  double distance_to_goal = 0.0;  // to the current waypoint when the mission ended
  double elapsed = 0.0;
  double path_length = 0.0;  // planned length of every leg started
  double distance_travelled = 0.0;
  uint32_t waypoints_reached = 0;
};

struct NavigationFeedback {
  NavigationState state = NavigationState::kIdle;
  Pose2 pose;
  double distance_remaining = 0.0;  // m along the current leg's path
  uint32_t waypoint_index = 0;      // path point being steered to
  uint32_t waypoint_count = 0;
  double stamp = 0.0;
  uint32_t mission_index = 0;  // mission waypoint being driven to
  uint32_t mission_count = 0;
  uint32_t laps_completed = 0;
  uint32_t waypoints_reached = 0;
  double distance_travelled = 0.0;  // m since the mission started (estimated poses)
  // s until the mission ends (until the end of the lap for an endless cyclic one), from the
  // distance left (current leg's path, straight lines after it) and the mission's average speed.
  double eta = 0.0;
  std::string behaviour;  // the motor behaviour in control
  std::vector<ProcessUtility> utilities;
  double danger = 0.0;                                 // moving-obstacle danger level mu
  std::vector<planning::MovingBody> moving_obstacles;  // confirmed by the detection process
  double speed_limit = 0.0;                            // m/s: a speed zone's limit where the robot is; 0: none
  uint32_t recoveries = 0;                             // recoveries run in this mission so far
  std::string reflex;                                  // the sonar reflex acting now ("FRONT level 2"); empty: none
  uint32_t reflexes = 0;                               // times the sonar reflex took a hand in this mission
};

struct NavigationStatus {
  uint64_t goal_id = 0;  // id of the active or last mission; 0 before the first
  bool active = false;
  bool paused = false;
  bool sensors_stale = false;
  std::string hold_reason;  // why the robot is held, while it is
  NavigationGoal goal;      // the current mission waypoint
  NavigationFeedback feedback;
  std::optional<NavigationResult> last_result;
  uint64_t sequence = 0;  // increments on every change
};

// The results of the last few missions by id: a handler streaming a mission finds its result
// after the mission ended, even when others ended since.
class RecentResults {
 public:
  void Add(uint64_t goal_id, const NavigationResult& result);
  std::optional<NavigationResult> Find(uint64_t goal_id) const;

 private:
  static constexpr size_t kKept = 64;
  std::vector<std::pair<uint64_t, NavigationResult>> results_;  // oldest first
};

const char* NavigationStateName(NavigationState s);
const char* OutcomeName(Outcome o);

}  // namespace navd::navigation
