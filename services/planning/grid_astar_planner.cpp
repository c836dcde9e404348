#include "services/planning/grid_astar_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "services/common/error.h"

namespace navd::planning {

std::string GridAStarPlanner::description() const {
  return dijkstra_ ? "Dijkstra's algorithm on the inflated grid (uniform-cost search)"
                   : "A* on the inflated grid, octile heuristic, no corner cutting";
}

std::vector<PlannerOptionSpec> GridAStarPlanner::options() const {
  return {{"diagonal", 1.0, "1: 8-connected moves, 0: 4-connected"}};
}

CellPath GridAStarPlanner::Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                                const PlannerOptions& options, const StopRequested& stop) const {
  const double diagonal_option = options.at("diagonal");
  if (diagonal_option != 0.0 && diagonal_option != 1.0) {
    throw Error(ErrorCode::kInvalidArgument, "options: 'diagonal' must be 0 or 1");
  }
  const bool diagonal = diagonal_option != 0.0;
  const int w = costmap.width(), h = costmap.height();
  const size_t n = static_cast<size_t>(w) * h;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  std::vector<float> g(n, kInf);
  std::vector<int32_t> parent(n, -1);
  std::vector<uint8_t> closed(n, 0);

  const float sqrt2 = std::sqrt(2.0f);
  auto heuristic = [&](int x, int y) -> float {
    if (dijkstra_) return 0.0f;
    const float dx = std::abs(x - goal.x), dy = std::abs(y - goal.y);
    return diagonal ? (dx + dy) + (sqrt2 - 2.0f) * std::min(dx, dy) : dx + dy;
  };

  struct Entry {
    float f;
    float g;
    int32_t index;
    bool operator<(const Entry& o) const { return f > o.f || (f == o.f && g < o.g); }  // min-heap, deeper first
  };
  std::priority_queue<Entry> open;
  const int32_t s = static_cast<int32_t>(start.y) * w + start.x;
  const int32_t t = static_cast<int32_t>(goal.y) * w + goal.x;
  g[s] = 0;
  open.push({heuristic(start.x, start.y), 0.0f, s});

  static constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  const int moves = diagonal ? 8 : 4;
  auto free = [&](int x, int y) { return x >= 0 && y >= 0 && x < w && y < h && !costmap.IsLethal({x, y}); };

  CellPath result;
  while (!open.empty()) {
    const Entry e = open.top();
    open.pop();
    if (closed[e.index]) continue;
    closed[e.index] = 1;
    // Checked on the first expansion and every 1024 after: cheap, and prompt.
    if ((++result.expansions & 1023) == 1 && stop && stop()) {
      throw Error(ErrorCode::kDeadlineExceeded, "planning stopped after " + std::to_string(result.expansions) +
                                                    " expansions: deadline exceeded or cancelled");
    }
    if (e.index == t) break;
    const int x = e.index % w, y = e.index / w;
    for (int k = 0; k < moves; ++k) {
      const int nx = x + kDx[k], ny = y + kDy[k];
      if (!free(nx, ny)) continue;
      if (k >= 4 && (!free(x + kDx[k], y) || !free(x, y + kDy[k]))) continue;  // no corner cutting
      const int32_t ni = ny * w + nx;
      if (closed[ni]) continue;
      const float ng = e.g + (k >= 4 ? sqrt2 : 1.0f);
      if (ng < g[ni]) {
        g[ni] = ng;
        parent[ni] = e.index;
        open.push({ng + heuristic(nx, ny), ng, ni});
      }
    }
  }
  if (!closed[t]) return result;
  for (int32_t i = t; i != -1; i = parent[i]) result.cells.push_back({i % w, i / w});
  std::reverse(result.cells.begin(), result.cells.end());
  return result;
}

}  // namespace navd::planning
