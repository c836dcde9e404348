#include "services/planning/path_transform_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "services/common/error.h"
#include "services/planning/grid_moves.h"
#include "services/planning/quaternary_heap.h"

namespace navd::planning {

std::string PathTransformPlanner::description() const {
  return plain_distance_ ? "Distance transform from the goal, descended from the start (book ch. 6)"
                         : "Path transform (Zelinsky): distance plus alpha-weighted obstacle discomfort (book ch. 6)";
}

std::vector<PlannerOptionSpec> PathTransformPlanner::options() const {
  if (plain_distance_) return {};
  return {{"alpha", 2.0, "weight of obstacle discomfort, per metre travelled (>= 0)"},
          {"influence", 1.0, "metres from an obstacle within which it causes discomfort (> 0)"}};
}

CellPath PathTransformPlanner::Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                                    const PlannerOptions& options, const StopRequested& stop) const {
  const double alpha = plain_distance_ ? 0.0 : options.at("alpha");
  const double influence = plain_distance_ ? 1.0 : options.at("influence");
  if (!(alpha >= 0.0)) throw Error(ErrorCode::kInvalidArgument, "options: 'alpha' must be >= 0");
  if (!(influence > 0.0)) throw Error(ErrorCode::kInvalidArgument, "options: 'influence' must be > 0");

  const OccupancyGrid& grid = costmap.grid();
  const int w = costmap.width(), h = costmap.height();
  const double res = grid.resolution();
  std::vector<double> discomfort;
  if (alpha > 0.0) {
    discomfort.resize(grid.cells().size());
    for (size_t i = 0; i < discomfort.size(); ++i) discomfort[i] = std::max(0.0, 1.0 - costmap.distance(i) / influence);
  }
  // Dijkstra from the goal over free cells (8-connected, no corner cutting): the transform.
  const uint8_t* lethal = costmap.lethal_data();
  auto free = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < w && y < h && !lethal[static_cast<size_t>(y) * w + x];
  };
  std::vector<double> value(static_cast<size_t>(w) * h, std::numeric_limits<double>::infinity());
  auto step_cost = [&](int32_t from, int32_t to, bool diagonal) {
    const double length = (diagonal ? M_SQRT2 : 1.0) * res;
    if (alpha == 0.0) return length;
    return length * (1.0 + alpha * 0.5 * (discomfort[from] + discomfort[to]));
  };
  QuaternaryHeap<> open;
  const int32_t g = goal.y * w + goal.x, s = start.y * w + start.x;
  value[g] = 0.0;
  open.push(0.0, g);
  CellPath result;
  while (!open.empty()) {
    const auto e = open.pop();
    if (e.key > value[e.node]) continue;  // stale
    if ((++result.expansions & 1023) == 1 && stop && stop()) {
      throw Error(ErrorCode::kDeadlineExceeded, "planning stopped: deadline exceeded or cancelled");
    }
    // The whole transform is the navigation function; it is complete once the start is settled.
    if (e.node == s) break;
    const int x = e.node % w, y = e.node / w;
    ForEachMove(x, y, free, [&](int nx, int ny, bool diagonal) {
      const int32_t n = ny * w + nx;
      const double v = e.key + step_cost(e.node, n, diagonal);
      if (v < value[n]) {
        value[n] = v;
        open.push(v, n);
      }
    });
  }
  if (!std::isfinite(value[s])) return result;
  // Steepest descent from the start: to the neighbour minimising step cost + value.
  int32_t c = s;
  result.cells.push_back(start);
  while (c != g && result.cells.size() <= value.size()) {
    const int x = c % w, y = c / w;
    int32_t best = -1;
    double best_v = std::numeric_limits<double>::infinity();
    ForEachMove(x, y, free, [&](int nx, int ny, bool diagonal) {
      const int32_t n = ny * w + nx;
      // The predecessor Dijkstra used: value[c] = step + value[n]; values strictly fall.
      const double through = step_cost(c, n, diagonal) + value[n];
      if (value[n] < value[c] && through < best_v) {
        best_v = through;
        best = n;
      }
    });
    if (best < 0) return {};  // cannot happen for a settled start; guards against loops
    c = best;
    result.cells.push_back({c % w, c / w});
  }
  if (c != g) result.cells.clear();
  return result;
}

}  // namespace navd::planning
