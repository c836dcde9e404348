#pragma once
// Voronoi Fast Marching (Garrido et al.; book chapter 4): obstacles are enlarged by the robot's
// size (the costmap's inflation), the Extended Voronoi Transform (distance to the nearest enlarged
// obstacle) is turned into a speed map F = log(1 + d) / log(1 + d_max) that is slow near walls
// and fast along the Voronoi skeleton, a wave is propagated from the goal through it with the
// Fast Marching Method (|grad T| = 1/F), and the path follows grad T down from the start. The path
// keeps to the middle of free space and is smooth; F at each point is also the speed limit (a
// fraction of the robot's top speed), returned with the path.
#include <vector>

#include "services/planning/global_planner.h"

namespace navd::planning {

// Arrival times of a front started at `goal` moving at `speed` (cells/step units scaled by the
// grid resolution: T is in metres at full speed). Cells with speed 0 are never reached
// (infinity). First-order upwind scheme on the 4-neighbourhood.
std::vector<double> FastMarch(int width, int height, double resolution, const std::vector<double>& speed,
                              const CellIndex& goal, const StopRequested& stop = {});

class VoronoiFastMarchingPlanner : public GlobalPlanner {
 public:
  std::string name() const override { return "voronoi_fast_marching"; }
  std::string description() const override {
    return "Voronoi Fast Marching: Fast Marching over the log Extended Voronoi Transform, gradient descent; "
           "returns a speed limit per point";
  }
  std::vector<PlannerOptionSpec> options() const override {
    return {{"saturation", 2.0, "metres of clearance at which the speed map reaches full speed (> 0)"},
            {"min_speed", 0.05, "speed fraction right next to the enlarged obstacles (0..1]"}};
  }
  Objective objective() const override { return Objective::kCost; }
  CellPath Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal, const PlannerOptions& options,
                const StopRequested& stop) const override;
};

}  // namespace navd::planning
