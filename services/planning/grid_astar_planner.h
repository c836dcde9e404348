#pragma once
// A* on the costmap's grid: 8-connected with the octile heuristic and no corner cutting (a
// diagonal step needs both side cells free), or 4-connected with the Manhattan heuristic. With
// heuristic weight 0 it is Dijkstra's algorithm, registered as its own planner.
#include "services/planning/global_planner.h"

namespace navd::planning {

class GridAStarPlanner : public GlobalPlanner {
 public:
  // dijkstra: plan with a zero heuristic (explores uniformly; same paths, more expansions).
  explicit GridAStarPlanner(bool dijkstra = false) : dijkstra_(dijkstra) {}
  std::string name() const override { return dijkstra_ ? "dijkstra" : "astar"; }
  std::string description() const override;
  std::vector<PlannerOptionSpec> options() const override;
  CellPath Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal, const PlannerOptions& options,
                const StopRequested& stop) const override;

 private:
  bool dijkstra_;
};

}  // namespace navd::planning
