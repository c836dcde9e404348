#pragma once
// A kinodynamic planner for book chapter 7's unicycle (OMPL's control planners; by default control
// RRT restarted for the whole time budget, the cheapest trajectory kept):
// state (x, y, θ, v, ω, t), acceleration inputs (u_v, u_ω) (Eq. 10), propagated by Euler steps
// of 0.05 s, and the cost of Eq. 15 over the people the request reports, each predicted at
// constant velocity:
//   I = ∫ (g1 + g2 + c_t) dt,
//   g1: the environment's valley (the costmap's decaying cost near walls, scaled by env_weight;
//       the chapter's c_y·y² is that valley for a street),
//   g2: per person, the chapter's four Gaussians in the person's frame (heading = direction of
//       walking): Parallel (ahead, elongated), Perpendicular (sideways), Rear (behind, round) and
//       the negative Attractor, weighted by the person's interest (0 for passers-by),
//   c_t: a price per second (our addition, so the robot does not dawdle where g1 + g2 = 0).
// The chapter gives no numbers for the weights or covariances; ours are documented at
// PersonCostModel. The terminal cost g3 is replaced by the goal region (the planner must reach
// it). States are invalid on lethal costmap cells and where a person's predicted body (its radius
// plus the robot's, the costmap's inflation radius) would touch the robot. Map frame, metres,
// radians, seconds.
#include <vector>

#include "services/planning/global_planner.h"
#include "services/planning/personal_space.h"
#include "services/planning/unicycle_model.h"

namespace navd::planning {

enum class KinodynamicAlgorithm {
  kRrtRestarts = 0,  // control RRT again and again for the time limit; the lowest Eq. 15 cost wins
  kSst = 1,          // OMPL's SST (asymptotically near-optimal; slow to improve in this 6-D space)
  kRrt = 2,          // control RRT, the first trajectory found
};

struct KinodynamicRequest {
  Point2 start = Point2::Zero();
  double start_yaw = 0.0, start_speed = 0.0;
  Point2 goal = Point2::Zero();
  double goal_tolerance = 0.25;  // metres
  double horizon = 120.0;        // seconds: states later than this are invalid
  double time_limit = 0.5;       // seconds of planning
  KinodynamicAlgorithm algorithm = KinodynamicAlgorithm::kRrtRestarts;
  double time_weight = 1.0;  // c_t, cost per second
  double env_weight = 2.0;   // g1 at the costmap's highest decaying cost
  UnicycleLimits limits;
  PersonCostModel people_model;
};

struct KinodynamicTrajectory {
  std::vector<Point2> points;               // one per 0.05 s propagation step, start first
  std::vector<double> yaws, speeds, times;  // per point
  double cost = 0.0;                        // Eq. 15 as above, along the returned trajectory
  uint64_t tree_size = 0;                   // vertices in the planners' trees, all rounds
  int rounds = 0;                           // trajectories found (RRT restarts)
};

// Throws navd::Error: kInvalidArgument for bad limits or an invalid start state, kNotFound when no
// trajectory reached the goal within time_limit, kDeadlineExceeded when stop() turns true first.
KinodynamicTrajectory PlanKinodynamic(const Costmap& costmap, const KinodynamicRequest& request,
                                      const std::vector<MovingBody>& moving, const StopRequested& stop = {});

// Eq. 15's integral along a trajectory (trapezoid rule between its points).
double TrajectoryCost(const Costmap& costmap, const KinodynamicRequest& request, const std::vector<MovingBody>& moving,
                      const std::vector<Point2>& points, const std::vector<double>& times);

class KinodynamicPlanner : public GlobalPlanner {
 public:
  std::string name() const override { return "kinodynamic"; }
  std::string description() const override {
    return "OMPL control planners for the book ch. 7 unicycle (acceleration inputs, Eq. 16 steering), Eq. 15 cost "
           "over predicted people";
  }
  std::vector<PlannerOptionSpec> options() const override;
  Objective objective() const override { return Objective::kCost; }
  bool time_budgeted() const override { return true; }
  CellPath Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal, const PlannerOptions& options,
                const StopRequested& stop) const override;
  bool plans_among_moving_bodies() const override { return true; }
  CellPath PlanInScene(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                       const PlannerOptions& options, const PlanningScene& scene,
                       const StopRequested& stop) const override;
};

}  // namespace navd::planning
