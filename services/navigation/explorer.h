#pragma once
// Autonomous exploration inside navd (seed 002 section 2.3, book chapter 4): a SLAM mapping run
// builds the map, which becomes the served map as it grows (so the planners, the executive and
// the telemetry all work on it); the robot localises from the SLAM poses (localiser "slam");
// NextExplorationStep picks the goal, and the executive drives there as a mission, with its brain,
// moving-obstacle avoidance and stops, until no reachable frontier is left. It runs in a thread of
// its own, deciding every `period` seconds of the daemon clock. Map frame, metres, seconds.
#include <atomic>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "services/common/clock.h"
#include "services/common/map_store.h"
#include "services/localization/localizer_selector.h"
#include "services/mapping/map_builder.h"
#include "services/navigation/exploration_goal_record.h"
#include "services/navigation/frontier_exploration.h"
#include "services/navigation/navigation_executive.h"

namespace navd::navigation {

struct ExplorerOptions {
  ExplorationMethod method = ExplorationMethod::kFrontier;
  ExplorationOptions exploration;
  mapping::MappingSessionOptions mapping;  // of the SLAM run it starts (mode is always SLAM)
  std::string planner;                     // of each leg; empty: the engine's default
  double period = 1.0;                     // s between decisions
  // A new goal is sent when the frontier chosen moves this far from the one being driven to, or
  // the mission is this old (its path was planned on an older map).
  double goal_switch_distance = 1.0;  // m
  double mission_refresh = 4.0;       // s
  // A goal the robot gets no closer to (by 5 cm) for this long is given up, as is one the
  // executive cannot plan to or whose mission fails.
  double stuck_after = 20.0;  // s
  double max_time = 0.0;      // s; 0: no limit
  // Added to the planners' inflation while exploring: walls seen once or twice sit a few
  // centimetres off, and a gap only a hair wider than the robot's inflated disc (a shelf beside a
  // wall) was entered and grazed (measured).
  double extra_inflation = 0.05;  // m
  // Walls seen better narrow the map's ways: one the robot came by can close below the clearance
  // behind it, shutting it in a pocket with no frontier of its own. Before calling the map
  // complete, the way out is looked for again along the robot's trail at the planners' own
  // inflation less `squeeze` (ExplorationOptions::squeeze_trail), and that leg is driven with the
  // planners' inflation lowered to the same: still a few centimetres wider than the robot (0.30 m
  // inflation, 0.20 m robot).
  double squeeze = 0.05;   // m
  int complete_after = 3;  // decisions in a row without a reachable frontier
};

enum class ExplorationState { kIdle, kExploring, kComplete, kStopped, kFailed };

struct ExplorationProgress {
  ExplorationState state = ExplorationState::kIdle;
  ExplorationMethod method = ExplorationMethod::kFrontier;
  std::string message;
  double explored_area = 0.0;  // m^2 known free
  int frontier_cells = 0;      // reachable at the last decision
  int goals = 0, goals_given_up = 0;
  double elapsed = 0.0;             // s
  double distance_travelled = 0.0;  // m, estimated poses
  Pose2 goal;                       // where the robot is sent now
};

class Explorer {
 public:
  Explorer(MapStore& maps, mapping::MapBuilder& builder, NavigationExecutive& executive,
           planning::PlanningEngine& planning, localization::LocalizerSelector& localizer, Clock& clock);
  ~Explorer();
  Explorer(const Explorer&) = delete;
  Explorer& operator=(const Explorer&) = delete;

  // Throws navd::Error: kFailedPrecondition (exploring already, a mission active, no pose, a
  // known-poses mapping run active), kInvalidArgument (options; the field named).
  ExplorationProgress Start(const ExplorerOptions& options);
  // Stops the robot, the exploration and its mapping run (the map stays served). Throws
  // navd::Error(kFailedPrecondition) when not exploring.
  ExplorationProgress Stop();
  ExplorationProgress Progress() const;

 private:
  void Run();
  // One decision at daemon time `now`; false once the exploration has ended.
  bool Decide(double now);
  // Follows the current goal's mission: ended (reached or failed), taken over, or stuck. False
  // once the exploration has ended.
  bool TrackMission(const Point2& position, double now);
  // Sends the robot towards `step`'s frontier, as far along its path as the costmap allows.
  void SendGoal(const ExplorationStep& step, const Point2& position, double now, bool squeeze);
  // The next step with the robot's trail passable at SqueezeClearance(), for a robot shut in a
  // pocket; nullopt when none (or squeezing would not lower the clearance).
  std::optional<ExplorationStep> SqueezedStep(const OccupancyGrid& map, const Pose2& robot) const;
  // The planners' inflation while exploring (theirs before it plus extra_inflation), and on a
  // squeeze leg (theirs less squeeze), in metres.
  double ExploringInflation() const;
  double SqueezeClearance() const;
  // Ends the exploration: cancels its mission, stops the mapping run, serves its last map.
  void End(ExplorationState state, const std::string& message);
  // The point of `path` farthest along that the executive can drive to (not lethal in the
  // current costmap), or nullopt.
  std::optional<Point2> ReachableEnd(const std::vector<Point2>& path) const;
  // Not chosen again: reached, or (given_up) unreachable or stuck, until the last retry.
  void Exclude(const Point2& frontier_goal, bool given_up);

  MapStore& maps_;
  mapping::MapBuilder& builder_;
  NavigationExecutive& executive_;
  planning::PlanningEngine& planning_;
  localization::LocalizerSelector& localizer_;
  Clock& clock_;

  std::mutex run_mutex_;  // one Start or Stop at a time
  std::thread thread_;
  std::atomic<bool> stop_{false};

  // The thread's own state.
  ExplorerOptions options_;
  double started_ = 0.0;
  double inflation_before_ = 0.0;  // the planners' inflation radius before exploring
  uint64_t served_version_ = ~0ULL;
  std::vector<Point2> visited_;
  Point2 last_position_ = Point2::Zero();
  uint64_t mission_ = 0;  // the executive's id of the current goal's mission
  double mission_started_ = 0.0;
  Point2 frontier_goal_ = Point2::Zero();  // the frontier cell the mission heads for
  double best_remaining_ = 0.0, last_progress_ = 0.0;
  int empty_decisions_ = 0;
  ExplorationGoalRecord goal_record_{0.0};

  mutable std::mutex mutex_;
  ExplorationProgress progress_;
};

}  // namespace navd::navigation
