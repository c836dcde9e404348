#include "services/planning/topological_graph_planner.h"

#include <algorithm>
#include <limits>
#include <queue>

#include "services/common/error.h"

namespace navd::planning {

CellPath TopologicalGraphPlanner::Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                                       const PlannerOptions& options, const StopRequested& stop) const {
  const auto places = cells_->Get(costmap, options.at("margin"));
  const Point2 start_point = costmap.grid().CellCenter(start), goal_point = costmap.grid().CellCenter(goal);
  const CellEntry from = places->Enter(costmap, start_point, 1.0, "start");
  const CellEntry to = places->Enter(costmap, goal_point, 1.0, "goal");
  const auto& cells = places->cells();
  const auto& doors = places->doorways();
  const int32_t n_cells = static_cast<int32_t>(cells.size());

  CellPath result;
  std::shared_ptr<const RouteTree> tree;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (table_map_ != places) {
      table_.clear();
      table_map_ = places;
    }
    if (auto it = table_.find(from.cell); it != table_.end()) tree = it->second;
  }
  if (tree) {
    ++hits_;
  } else {
    ++misses_;
    // Dijkstra from the start's place over every node (the whole table row at once).
    auto built = std::make_shared<RouteTree>();
    const size_t n = cells.size() + doors.size();
    built->parent.assign(n, -1);
    std::vector<double> dist(n, std::numeric_limits<double>::infinity());
    auto point = [&](int32_t node) {
      return node < n_cells ? cells[node].centre() : places->DoorwayPoint(node - n_cells, 0.5);
    };
    using Item = std::pair<double, int32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    dist[from.cell] = 0.0;
    open.push({0.0, from.cell});
    while (!open.empty()) {
      const double d = open.top().first;
      const int32_t u = open.top().second;
      open.pop();
      if (d > dist[u]) continue;
      if ((++result.expansions & 255) == 0 && stop && stop())
        throw Error(ErrorCode::kDeadlineExceeded, "topological planning stopped: deadline exceeded or cancelled");
      auto relax = [&](int32_t v) {
        const double nd = d + Distance(point(u), point(v));
        if (nd < dist[v]) {
          dist[v] = nd;
          built->parent[v] = u;
          open.push({nd, v});
        }
      };
      if (u < n_cells) {
        for (const int32_t door : cells[u].doorways) relax(n_cells + door);
      } else {
        for (const int32_t c : doors[u - n_cells].cells) relax(c);
      }
    }
    tree = built;
    std::lock_guard<std::mutex> lock(mutex_);
    if (table_map_ == places) table_[from.cell] = tree;
  }

  if (to.cell != from.cell && tree->parent[to.cell] < 0)
    throw Error(ErrorCode::kNotFound,
                "no path: the goal's place is not connected to the start's in the topological graph");
  // The route read backwards from the goal's place: a border node's parent is the place it was
  // crossed from.
  std::vector<Point2> way{to.point};
  for (int32_t node = to.cell; node != from.cell; node = tree->parent[node]) {
    if (node < n_cells) continue;
    const int32_t door = node - n_cells;
    const auto [leave, enter] = places->Crossing(door, tree->parent[node], places->DoorwayPoint(door, 0.5));
    way.push_back(enter);
    way.push_back(leave);
  }
  way.push_back(from.point);
  if (from.point != start_point) way.push_back(start_point);
  std::reverse(way.begin(), way.end());
  if (to.point != goal_point) way.push_back(goal_point);
  result.cells = {start, goal};
  result.points = way;
  return result;
}

}  // namespace navd::planning
