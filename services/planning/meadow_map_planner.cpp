#include "services/planning/meadow_map_planner.h"

#include <algorithm>
#include <limits>
#include <queue>

#include "services/common/error.h"

namespace navd::planning {

MeadowPath PlanOnMeadowMap(const ConvexCellMap& meadows, const Costmap& costmap, const Point2& start,
                           const Point2& goal, double entry_reach, const StopRequested& stop) {
  const CellEntry from = meadows.Enter(costmap, start, entry_reach, "start");
  const CellEntry to = meadows.Enter(costmap, goal, entry_reach, "goal");
  MeadowPath path;
  std::vector<Point2> way;
  if (from.cell == to.cell) {
    way = {from.point, to.point};  // one convex polygon: straight across
  } else {
    const auto& cells = meadows.cells();
    const auto& doors = meadows.doorways();
    // Nodes: the border midpoints, then the goal (index doors.size()).
    const int32_t goal_node = static_cast<int32_t>(doors.size());
    std::vector<double> g(doors.size() + 1, std::numeric_limits<double>::infinity());
    std::vector<int32_t> parent(doors.size() + 1, -1);
    auto node_point = [&](int32_t n) { return n == goal_node ? to.point : meadows.DoorwayPoint(n, 0.5); };
    using Item = std::pair<double, int32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    auto relax = [&](int32_t n, double cost, int32_t from_node) {
      if (cost < g[n]) {
        g[n] = cost;
        parent[n] = from_node;
        open.push({cost + Distance(node_point(n), to.point), n});
      }
    };
    for (const int32_t d : cells[from.cell].doorways) relax(d, Distance(from.point, node_point(d)), -1);
    while (!open.empty()) {
      const auto [f, n] = open.top();
      open.pop();
      if (f - Distance(node_point(n), to.point) > g[n] + 1e-12) continue;  // stale
      if (n == goal_node) break;
      if ((++path.expansions & 255) == 0 && stop && stop())
        throw Error(ErrorCode::kDeadlineExceeded, "meadow map planning stopped: deadline exceeded or cancelled");
      const Point2 p = node_point(n);
      for (const int32_t cell : doors[n].cells) {
        if (cell == to.cell) relax(goal_node, g[n] + Distance(p, to.point), n);
        for (const int32_t d : cells[cell].doorways)
          if (d != n) relax(d, g[n] + Distance(p, node_point(d)), n);
      }
    }
    if (parent[goal_node] < 0)
      throw Error(ErrorCode::kNotFound, "no path: no chain of meadows joins the start's polygon to the goal's");
    // Walk back, crossing each border from the cell the route came through.
    std::vector<int32_t> route;
    for (int32_t n = parent[goal_node]; n >= 0; n = parent[n]) route.push_back(n);
    std::reverse(route.begin(), route.end());
    way.push_back(from.point);
    int32_t cell = from.cell;
    for (const int32_t n : route) {
      const auto [leave, enter] = meadows.Crossing(n, cell, node_point(n));
      way.push_back(leave);
      way.push_back(enter);
      cell = doors[n].other(cell);
    }
    way.push_back(to.point);
  }
  if (from.point != start) path.points.push_back(start);
  path.points.insert(path.points.end(), way.begin(), way.end());
  if (to.point != goal) path.points.push_back(goal);
  for (size_t i = 1; i < path.points.size(); ++i) path.length += Distance(path.points[i - 1], path.points[i]);
  return path;
}

CellPath MeadowMapPlanner::Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                                const PlannerOptions& options, const StopRequested& stop) const {
  const auto meadows = cells_->Get(costmap, options.at("margin"));
  const MeadowPath path =
      PlanOnMeadowMap(*meadows, costmap, costmap.grid().CellCenter(start), costmap.grid().CellCenter(goal), 1.0, stop);
  CellPath result;
  result.cells = {start, goal};
  result.points = path.points;
  result.expansions = path.expansions;
  return result;
}

}  // namespace navd::planning
