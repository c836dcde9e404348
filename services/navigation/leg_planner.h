#pragma once
// The navigation behaviour's planning. A mission is checked from the robot's pose when it starts
// (every waypoint and leg); each leg the navigator asks for is planned from the pose estimate round
// what the sensors found (tracked obstacles within planning_range, sonar and bumper discs, the 3-D
// layer's cells), and replanned when something comes to lie across it; a start outside the
// navigation grid begins seed 000's drive back onto it (GridReentry, states 2-5) rather than
// failing the mission. Map frame, metres, seconds of the daemon's clock.
#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

#include "services/common/error.h"
#include "services/navigation/grid_reentry.h"
#include "services/navigation/moving_obstacle_detection.h"
#include "services/navigation/navigator.h"
#include "services/navigation/sensed_obstacles.h"
#include "services/planning/planning_engine.h"

namespace navd::navigation {

struct LegPlannerOptions {
  double robot_radius = 0.2;    // m
  double planning_range = 3.0;  // m: seed 000's Delta, within which obstacles enter the plans
  GridReentryOptions reentry;
};

class LegPlanner {
 public:
  LegPlanner(planning::PlanningEngine& planning, Navigator& navigator, const MovingObstacleDetection& detection,
             const SensedObstacles& sensed, const LegPlannerOptions& options)
      : planning_(planning),
        navigator_(navigator),
        detection_(detection),
        sensed_(sensed),
        options_(options),
        reentry_(options.reentry) {}

  // Checks `mission` from `from` and starts it on the navigator with `planner`; returns its id.
  // Throws the planning engine's navd::Error, its fields named.
  uint64_t StartMission(const Mission& mission, const std::string& planner, bool preempt, const Pose2& from, double now,
                        const planning::StopRequested& stop);
  // Plans the leg the navigator asks for, if any, from `pose`; a start off the grid starts (or
  // continues) the drive back onto it, any other failure ends the mission.
  void PlanLeg(const Pose2& pose, double now);
  // Seed 000's states 3-5 while the robot is outside the grid: the command that leads it back on
  // (the navigator holds, its status says why); nullopt on the grid.
  std::optional<WheelSpeeds> DriveBackOntoGrid(const Pose2& pose, bool fresh, double now);
  // Asks the navigator to replan a leg that a tracked obstacle (not among people, whom the crowd
  // controller steers round), a sensed disc or cell, or a changed map now blocks.
  void ReplanIfBlocked(const Pose2& pose, bool among_people);
  // What the plans go round besides the map, seen from `pose`.
  planning::PlanningScene Scene(const Pose2& pose) const;

 private:
  // Whether `e` says the robot is outside the navigation grid (the planner refuses its start) and
  // the laser can lead it back.
  bool StartsOffGrid(const Error& e) const;
  // The nearest point where a leg could start (a costmap cell that is not lethal) within
  // kReentrySearch of `p` along each axis, reachable from `p` or, from inside a wall (an estimate
  // off the truth), through walls; map frame.
  std::optional<Point2> NearestGridPoint(const Point2& p) const;

  planning::PlanningEngine& planning_;
  Navigator& navigator_;
  const MovingObstacleDetection& detection_;
  const SensedObstacles& sensed_;
  LegPlannerOptions options_;
  GridReentry reentry_;      // control thread only
  std::string reentry_why_;  // what the planner said of the start
  double reentry_checked_at_ = -1e9;
  uint64_t reentry_mission_ = 0;  // the mission the reentry is for
  // The served map's version the current leg was planned on (set by gRPC and control threads).
  std::atomic<uint64_t> leg_map_version_{0};
  std::string planner_;  // the active mission's planner
};

}  // namespace navd::navigation
