#pragma once
// Seed 004's meadow map planner: the free space as convex polygons (here the convex navigation
// grid's cells, generated rather than drawn by hand), a graph whose nodes are the midpoints of the
// borders two polygons share, and A* over it (Euclidean edge costs and heuristic). Two midpoints
// are joined when they lie on one polygon, so every edge crosses a single convex, free polygon.
// The start and goal join the midpoints of their own polygons (the seed snaps them to the nearest
// node, which may lie behind a wall). Map frame, metres.
#include <memory>

#include "services/planning/convex_cell_map.h"
#include "services/planning/global_planner.h"

namespace navd::planning {

struct MeadowPath {
  std::vector<Point2> points;  // start, border midpoints, goal
  double length = 0.0;         // metres
  uint64_t expansions = 0;     // graph nodes settled
};

// Throws navd::Error(kNotFound) when start or goal is off the map's polygons or no route joins
// them, kDeadlineExceeded when stop() turns true.
MeadowPath PlanOnMeadowMap(const ConvexCellMap& meadows, const Costmap& costmap, const Point2& start,
                           const Point2& goal, double entry_reach, const StopRequested& stop = {});

class MeadowMapPlanner : public GlobalPlanner {
 public:
  explicit MeadowMapPlanner(std::shared_ptr<ConvexCellMapCache> cells) : cells_(std::move(cells)) {}
  std::string name() const override { return "meadow_map"; }
  std::string description() const override {
    return "Seed 004 meadow map: convex polygons, A* over the midpoints of the borders they share";
  }
  std::vector<PlannerOptionSpec> options() const override {
    return {{"margin", 0.05, "metres of contraction beyond the costmap's inflation"}};
  }
  Objective objective() const override { return Objective::kCost; }
  CellPath Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal, const PlannerOptions& options,
                const StopRequested& stop) const override;

 private:
  std::shared_ptr<ConvexCellMapCache> cells_;
};

}  // namespace navd::planning
