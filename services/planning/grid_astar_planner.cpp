#include "services/planning/grid_astar_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "services/common/error.h"
#include "services/planning/grid_moves.h"
#include "services/planning/quaternary_heap.h"
#include "services/planning/search_workspace.h"

namespace navd::planning {

std::string GridAStarPlanner::description() const {
  return dijkstra_ ? "Dijkstra's algorithm on the inflated grid (uniform-cost search)"
                   : "A* on the inflated grid, octile heuristic, no corner cutting";
}

std::vector<PlannerOptionSpec> GridAStarPlanner::options() const {
  return {{"diagonal", 1.0, "1: 8-connected moves, 0: 4-connected"},
          {"cost_weight", 1.0, "step cost = length * (1 + cost_weight * cost / 252) on the costmap's decay layer (>= 0)"}};
}

namespace {

// The search loop, compiled once per combination so the inner loop carries no branches on them:
// kHeuristic (A*; Dijkstra without), kCost (steps weighed by the decay layer).
template <bool kHeuristic, bool kCost>
CellPath Search(const Costmap& costmap, const CellIndex& start, const CellIndex& goal, bool diagonal,
                double cost_weight, const StopRequested& stop) {
  const int w = costmap.width();
  const size_t n = static_cast<size_t>(w) * costmap.height();
  // Doubles: distinct 8-connected path lengths a + b*sqrt(2) can differ by ~1e-5 on large maps,
  // below float resolution.
  SearchWorkspace& ws = SearchWorkspace::ForThisThread(n);
  const uint8_t* moves = costmap.move_data();
  const uint8_t* cost = costmap.cost_data();
  // Step cost = length * (1 + cost_weight * mean cost of the two cells / kMaxCost).
  const double per_cost = 0.5 * cost_weight / Costmap::kMaxCost;
  const unsigned allowed = diagonal ? 0xFFu : 0x0Fu;
  int32_t offset[8];
  double length[8];
  for (int k = 0; k < 8; ++k) {
    offset[k] = kGridMoves[k].dy * w + kGridMoves[k].dx;
    length[k] = kGridMoves[k].diagonal ? M_SQRT2 : 1.0;
  }

  // Inflating h by 1e-9 breaks the vast ties of octile distance towards the goal (far fewer
  // expansions in open space) without costing optimality: for paths under ~1e4 cells, 1e-9 of the
  // length is below the smallest gap between two distinct path lengths.
  constexpr double kTieBreak = 1.0 + 1e-9;
  auto heuristic = [&](int x, int y) -> double {
    if constexpr (!kHeuristic) return 0.0;
    const double dx = std::abs(x - goal.x), dy = std::abs(y - goal.y);
    return kTieBreak * (diagonal ? (dx + dy) + (M_SQRT2 - 2.0) * std::min(dx, dy) : dx + dy);
  };

  thread_local QuaternaryHeap<> open;
  open.clear();
  const int32_t s = static_cast<int32_t>(start.y) * w + start.x;
  const int32_t t = static_cast<int32_t>(goal.y) * w + goal.x;
  ws.Set(s, 0.0, -1);
  open.push(heuristic(start.x, start.y), s);

  CellPath result;
  while (!open.empty()) {
    const int32_t current = open.pop().node;
    if (ws.closed(current)) continue;  // a stale duplicate
    ws.Close(current);
    // Checked on the first expansion and every 1024 after: cheap, and prompt.
    if ((++result.expansions & 1023) == 1 && stop && stop()) {
      throw Error(ErrorCode::kDeadlineExceeded, "planning stopped after " + std::to_string(result.expansions) +
                                                    " expansions: deadline exceeded or cancelled");
    }
    if (current == t) break;
    const int x = current % w, y = current / w;
    const double g_current = ws.g(current);
    // Lengths stay the heuristic's lower bound: penalties only add.
    [[maybe_unused]] const double from_cost = kCost ? 1.0 + per_cost * cost[current] : 1.0;
    for (unsigned m = moves[current] & allowed; m != 0; m &= m - 1) {
      const int k = __builtin_ctz(m);
      const int32_t ni = current + offset[k];
      if (ws.closed(ni)) continue;
      double step = length[k];
      if constexpr (kCost) step *= from_cost + per_cost * cost[ni];
      const double ng = g_current + step;
      if (ng < ws.g(ni)) {
        ws.Set(ni, ng, current);
        open.push(ng + heuristic(x + kGridMoves[k].dx, y + kGridMoves[k].dy), ni);
      }
    }
  }
  if (!ws.closed(t)) return result;
  for (int32_t i = t; i != -1; i = ws.parent(i)) result.cells.push_back({i % w, i / w});
  std::reverse(result.cells.begin(), result.cells.end());
  return result;
}

}  // namespace

CellPath GridAStarPlanner::Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                                const PlannerOptions& options, const StopRequested& stop) const {
  const double diagonal_option = options.at("diagonal");
  if (diagonal_option != 0.0 && diagonal_option != 1.0) {
    throw Error(ErrorCode::kInvalidArgument, "options: 'diagonal' must be 0 or 1");
  }
  const bool diagonal = diagonal_option != 0.0;
  const double cost_weight = options.at("cost_weight");
  if (!(cost_weight >= 0.0)) throw Error(ErrorCode::kInvalidArgument, "options: 'cost_weight' must be >= 0");
  const bool weigh_cost = cost_weight > 0.0 && costmap.cost_data() != nullptr;
  if (dijkstra_) {
    return weigh_cost ? Search<false, true>(costmap, start, goal, diagonal, cost_weight, stop)
                      : Search<false, false>(costmap, start, goal, diagonal, cost_weight, stop);
  }
  return weigh_cost ? Search<true, true>(costmap, start, goal, diagonal, cost_weight, stop)
                    : Search<true, false>(costmap, start, goal, diagonal, cost_weight, stop);
}

}  // namespace navd::planning
