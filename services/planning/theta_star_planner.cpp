#include "services/planning/theta_star_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "services/common/error.h"
#include "services/planning/grid_moves.h"

namespace navd::planning {

bool CellsSeeEachOther(const Costmap& costmap, const CellIndex& a, const CellIndex& b) {
  return costmap.SegmentFree(costmap.grid().CellCenter(a), costmap.grid().CellCenter(b));
}

CellPath ThetaStarPlanner::Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                                const PlannerOptions&, const StopRequested& stop) const {
  const int w = costmap.width(), h = costmap.height();
  const size_t n = static_cast<size_t>(w) * h;
  std::vector<double> g(n, std::numeric_limits<double>::infinity());
  std::vector<int32_t> parent(n, -1);
  std::vector<uint8_t> closed(n, 0);
  auto index = [w](int x, int y) { return static_cast<int32_t>(y) * w + x; };
  auto cell = [w](int32_t i) { return CellIndex{i % w, i / w}; };
  auto dist = [](const CellIndex& p, const CellIndex& q) { return std::hypot(p.x - q.x, p.y - q.y); };
  auto free = [&](int x, int y) { return x >= 0 && y >= 0 && x < w && y < h && !costmap.IsLethal({x, y}); };

  struct Entry {
    double f;
    double g;
    int32_t index;
    bool operator<(const Entry& o) const { return f > o.f || (f == o.f && g < o.g); }
  };
  std::priority_queue<Entry> open;
  const int32_t s = index(start.x, start.y), t = index(goal.x, goal.y);
  g[s] = 0.0;
  parent[s] = s;
  open.push({dist(start, goal), 0.0, s});

  CellPath result;
  while (!open.empty()) {
    const Entry e = open.top();
    open.pop();
    if (closed[e.index]) continue;
    closed[e.index] = 1;
    CountExpansion(result.expansions, stop);
    if (e.index == t) break;
    const CellIndex c = cell(e.index);
    const CellIndex p = cell(parent[e.index]);
    ForEachMove(c.x, c.y, free, [&](int nx, int ny, bool diagonal) {
      const int32_t ni = index(nx, ny);
      if (closed[ni]) return;
      const CellIndex nc{nx, ny};
      // Path 2 (through the parent) when the parent sees the neighbour; else path 1 (grid step).
      double candidate;
      int32_t via;
      if (CellsSeeEachOther(costmap, p, nc)) {
        candidate = g[parent[e.index]] + dist(p, nc);
        via = parent[e.index];
      } else {
        candidate = g[e.index] + (diagonal ? M_SQRT2 : 1.0);
        via = e.index;
      }
      if (candidate < g[ni]) {
        g[ni] = candidate;
        parent[ni] = via;
        open.push({candidate + dist(nc, goal), candidate, ni});
      }
    });
  }
  if (!closed[t]) return result;
  for (int32_t i = t;; i = parent[i]) {
    result.cells.push_back(cell(i));
    if (i == s) break;
  }
  std::reverse(result.cells.begin(), result.cells.end());
  return result;
}

}  // namespace navd::planning
