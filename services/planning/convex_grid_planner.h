#pragma once
// Seed 000's grid navigation planner (section 4.1.2) over the convex navigation grid: Dijkstra
// from the start's cell across the cells, each step through a random waypoint on the side the two
// cells share, the distance so far measured along those waypoints; segments passing a detected
// moving obstacle (closer to the robot than Δ) within its radius plus a margin take a large
// penalty; the search is repeated n times with fresh waypoints and the shortest path kept; finally
// waypoints are interpolated so consecutive ones are at most d_wp apart. Map frame, metres.
//
// The seed gives no values for μ, Δ, n or d_wp; ours are the option defaults below.
#include <memory>
#include <vector>

#include "services/planning/convex_cell_map.h"
#include "services/planning/global_planner.h"

namespace navd::planning {

struct MovingObstacleCircle {
  Point2 centre = Point2::Zero();  // map frame, metres
  double radius = 0.0;             // metres, already enlarged by the detector
};

struct ConvexGridOptions {
  int iterations = 10;            // n
  double waypoint_spacing = 0.5;  // d_wp, metres
  double obstacle_range = 3.0;    // Δ, metres from the start
  double obstacle_margin = 0.2;   // metres added to an obstacle's radius
  double entry_reach = 1.0;       // metres a start or goal in the margin may be from the grid
  uint64_t seed = 1;
};

struct ConvexGridPath {
  std::vector<Point2> points;                     // start first, goal last
  double length = 0.0;                            // metres, without penalties
  bool penalised = false;                         // the best path still passes an obstacle circle
  uint64_t expansions = 0;                        // cells settled over all iterations
  std::vector<double> best_length_per_iteration;  // the best so far after each iteration
};

// Throws navd::Error: kNotFound when start or goal is off the grid or the goal's cell cannot be
// reached, kDeadlineExceeded when stop() turns true.
ConvexGridPath PlanOnConvexGrid(const ConvexCellMap& grid, const Costmap& costmap, const Point2& start,
                                const Point2& goal, const ConvexGridOptions& options,
                                const std::vector<MovingObstacleCircle>& obstacles = {},
                                const StopRequested& stop = {});

class ConvexGridPlanner : public GlobalPlanner {
 public:
  explicit ConvexGridPlanner(std::shared_ptr<ConvexCellMapCache> cells) : cells_(std::move(cells)) {}
  std::string name() const override { return "convex_grid"; }
  std::string description() const override {
    return "Seed 000 convex navigation grid: contracted map cut into convex cells, Dijkstra over cells through "
           "random waypoints on shared sides, best of n, interpolated to d_wp";
  }
  std::vector<PlannerOptionSpec> options() const override;
  Objective objective() const override { return Objective::kCost; }
  CellPath Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal, const PlannerOptions& options,
                const StopRequested& stop) const override;
  // The scene's moving bodies are the detected moving obstacles (circles where they are now).
  bool plans_among_moving_bodies() const override { return true; }
  CellPath PlanInScene(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                       const PlannerOptions& options, const PlanningScene& scene,
                       const StopRequested& stop) const override;

 private:
  std::shared_ptr<ConvexCellMapCache> cells_;
};

}  // namespace navd::planning
