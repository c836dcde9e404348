#pragma once
// Book chapter 1's topological route planning: a graph of places and the ways between them,
// Dijkstra's shortest routes from a place to every other kept in a table of computed routes (the
// chapter's "reminiscent table"), and a query answered from the table when it can be. Places are
// the convex navigation grid's cells (rooms, corridor pieces), ways the borders they share; an
// edge joins a cell's centre to each of its borders' midpoints, weighted by their distance. The
// route driven goes start -> the borders crossed -> goal (each leg inside one convex cell). The
// table belongs to one map: a new map (or margin) starts an empty one. Map frame, metres.
#include <atomic>
#include <memory>
#include <mutex>
#include <unordered_map>

#include "services/planning/convex_cell_map.h"
#include "services/planning/global_planner.h"

namespace navd::planning {

class TopologicalGraphPlanner : public GlobalPlanner {
 public:
  explicit TopologicalGraphPlanner(std::shared_ptr<ConvexCellMapCache> cells) : cells_(std::move(cells)) {}
  std::string name() const override { return "topological"; }
  std::string description() const override {
    return "Book ch. 1 topological graph: places (convex cells) and their shared borders, Dijkstra routes kept "
           "in a table of computed routes";
  }
  std::vector<PlannerOptionSpec> options() const override {
    return {{"margin", 0.05, "metres of contraction beyond the costmap's inflation"}};
  }
  Objective objective() const override { return Objective::kCost; }
  // expansions is 0 when the route came from the table.
  CellPath Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal, const PlannerOptions& options,
                const StopRequested& stop) const override;

  uint64_t table_hits() const { return hits_; }
  uint64_t table_misses() const { return misses_; }

 private:
  // Dijkstra's tree from one place: each node's predecessor (cells first, then borders), -1 at
  // the root and for nodes it cannot reach.
  struct RouteTree {
    std::vector<int32_t> parent;
  };

  std::shared_ptr<ConvexCellMapCache> cells_;
  mutable std::mutex mutex_;
  mutable std::shared_ptr<const ConvexCellMap> table_map_;  // the map the table belongs to
  mutable std::unordered_map<int32_t, std::shared_ptr<const RouteTree>> table_;
  mutable std::atomic<uint64_t> hits_{0}, misses_{0};
};

}  // namespace navd::planning
