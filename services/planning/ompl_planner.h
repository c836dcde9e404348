#pragma once
// Sampling-based planners from OMPL in SE(2): RRT-Connect, RRT*, PRM*, Informed RRT* and BIT*,
// in the plain SE(2) space or, for car-like robots, the Dubins (forward only) or Reeds-Shepp
// spaces with a minimum turning radius. A state is valid when its cell is free on the inflated
// costmap, which for navd's disc robots is exactly the footprint test. The solution is simplified
// (shortcutting, smoothing) by OMPL and interpolated; points are in the map frame, metres.
// OMPL's headers stay in ompl_planner.cpp so the rest of the build does not pay for them.
#include "services/planning/global_planner.h"

namespace navd::planning {

class OmplPlanner : public GlobalPlanner {
 public:
  enum class Algorithm { kRrtConnect, kRrtStar, kPrmStar, kInformedRrtStar, kBitStar };
  explicit OmplPlanner(Algorithm algorithm) : algorithm_(algorithm) {}
  std::string name() const override;
  std::string description() const override;
  std::vector<PlannerOptionSpec> options() const override;  // time_limit, space, turning_radius, yaws
  // Sampling gives no optimality guarantee within a time budget: judged on finding a path.
  Objective objective() const override { return Objective::kCost; }
  bool time_budgeted() const override { return true; }
  CellPath Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal, const PlannerOptions& options,
                const StopRequested& stop) const override;

 private:
  Algorithm algorithm_;
};

}  // namespace navd::planning
