#pragma once
// Jump Point Search (Harabor & Grastien, AAAI 2011; the no-corner-cutting rules of their ICAPS
// 2014 sequel): A* on the 8-connected grid that expands only jump points. From a node it runs
// straight or diagonally until the run meets the goal or a cell where an optimal path may turn
// (a "forced neighbour": a wall beside the run ends and the side cell opens), and skips every cell
// in between, whose successors other paths reach at least as cheaply. Paths are exactly as short
// as A*'s (octile length, no corner cutting), at a fraction of the expansions on open or
// wide-corridor maps. Every step costs its length: the costmap's decay layer is not weighed (use
// astar or dijkstra for clearance-aware paths).
#include "services/planning/global_planner.h"

namespace navd::planning {

class JumpPointPlanner : public GlobalPlanner {
 public:
  std::string name() const override { return "jps"; }
  std::string description() const override;
  std::vector<PlannerOptionSpec> options() const override { return {}; }
  CellPath Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal, const PlannerOptions& options,
                const StopRequested& stop) const override;
};

}  // namespace navd::planning
