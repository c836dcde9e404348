#pragma once
// Theta* (Nash, Daniel, Koenig and Felner, 2007): A* whose nodes may take any visible ancestor as
// parent, giving any-angle paths between cell centres. Line of sight is Costmap::SegmentFree,
// which treats a segment through the exact corner of a blocked cell as blocked: the same
// no-corner-cutting rule as A*. Each parent update is no longer than the A* update it
// replaces (triangle inequality), so paths come out no longer than A*'s; tests check this on the
// MovingAI scenarios and random maps.
#include "services/planning/global_planner.h"

namespace navd::planning {

class ThetaStarPlanner : public GlobalPlanner {
 public:
  std::string name() const override { return "thetastar"; }
  std::string description() const override {
    return "Theta*: any-angle A* with line-of-sight parent updates on the inflated grid";
  }
  std::vector<PlannerOptionSpec> options() const override { return {}; }
  Objective objective() const override { return Objective::kAnyAngleLength; }
  CellPath Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal, const PlannerOptions& options,
                const StopRequested& stop) const override;
};

// True when the segment between the centres of cells a and b crosses only free cells.
bool CellsSeeEachOther(const Costmap& costmap, const CellIndex& a, const CellIndex& b);

}  // namespace navd::planning
