#pragma once
// Book chapter 7's model-predictive loop run ahead of time, for a whole trajectory to a goal: the
// planning service's way to the crowd RRT (navd's controller runs the same loop live, against
// what the laser sees: navigation/crowd_controller.h). Each round plans with PlanCrowdRrt from
// where the last round left the robot, keeps the plan's first `execute` seconds (the chapter
// executes 2 s of each plan) and carries the people on at their velocities by as much; the next
// plan starts from what is left of the last. A round's goal is the point `lookahead` metres along
// the route (a grid path from the start to the goal, through the map's walls), and the route is
// its valley, so the route says where to go and the crowd RRT how to get there among people. Once
// the goal is a round's goal, it is an end to that round's tree (CrowdRrtRequest::goal_tolerance),
// so a plan that reaches it is taken however short. The trajectory ends where it first comes
// within goal_tolerance of the goal, at speed: the crowd RRT has no notion of stopping on a point.
// Map frame, metres, radians, seconds.
#include <cstdint>
#include <vector>

#include "services/planning/crowd_rrt.h"

namespace navd::planning {

struct CrowdRouteRequest {
  UnicycleState start;
  Point2 goal = Point2::Zero();
  double goal_tolerance = 0.25;    // m
  std::vector<Point2> route;       // start to goal, clear of walls (at least two points)
  std::vector<MovingBody> people;  // now, with velocities (m/s) for the prediction
  UnicycleLimits limits;
  double execute = 2.0;     // s of each plan kept
  double lookahead = 12.0;  // m along the route: each round's goal
  double max_time = 120.0;  // s: a trajectory that has not arrived by then is not found
  uint64_t seed = 1;
};

struct CrowdRoute {
  std::vector<UnicycleState> states;  // start first; t from the start
  int plans = 0;
  int vertices = 0;  // in all the rounds' trees
};

// Throws navd::Error: kInvalidArgument (a route of fewer than two points, non-finite input,
// options out of range), kNotFound (no arrival within max_time), kDeadlineExceeded (stop() turned
// true).
CrowdRoute PlanCrowdRoute(const Costmap& costmap, const CrowdRouteRequest& request, const CrowdRrtOptions& options,
                          const StopRequested& stop = {});

}  // namespace navd::planning
