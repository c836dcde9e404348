#pragma once
// The path transform of Zelinsky (book chapter 6, Eq. 1): a navigation function grown from the
// goal through free space whose value at c is min over paths p from c to the goal of
//   length(p) + alpha * sum of obstacle(c_i) along p,
// with obstacle(c) = max(0, 1 - d(c) / influence) the discomfort of the nearest obstacle at
// distance d(c) (from the distance transform). The sum is taken per metre travelled, so alpha does
// not depend on the grid resolution. The robot descends the transform from the start. With
// alpha = 0 it is the plain distance transform ("distance_transform").
#include "services/planning/global_planner.h"

namespace navd::planning {

class PathTransformPlanner : public GlobalPlanner {
 public:
  // plain_distance: register as "distance_transform" (alpha fixed at 0).
  explicit PathTransformPlanner(bool plain_distance = false) : plain_distance_(plain_distance) {}
  std::string name() const override { return plain_distance_ ? "distance_transform" : "path_transform"; }
  std::string description() const override;
  std::vector<PlannerOptionSpec> options() const override;
  Objective objective() const override { return plain_distance_ ? Objective::kGridLength : Objective::kCost; }
  CellPath Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal, const PlannerOptions& options,
                const StopRequested& stop) const override;

 private:
  bool plain_distance_;
};

}  // namespace navd::planning
