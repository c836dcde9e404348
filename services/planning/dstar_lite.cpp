#include "services/planning/dstar_lite.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "services/common/error.h"
#include "services/planning/grid_moves.h"

namespace navd::planning {
namespace {
const OctileCost kInf = OctileCost::Infinite();
constexpr OctileCost kStraight = OctileCost::Steps(1, 0);
constexpr OctileCost kDiagonal = OctileCost::Steps(0, 1);
}  // namespace

DStarLite::DStarLite(const Costmap& costmap, const CellIndex& start, const CellIndex& goal)
    : width_(costmap.width()),
      height_(costmap.height()),
      blocked_(costmap.lethal_data(), costmap.lethal_data() + static_cast<size_t>(width_) * height_),
      node_(blocked_.size()),
      start_(start),
      goal_(goal),
      last_(start) {
  // A path visits each cell once, so the grid's size bounds every finite cost (keys add the
  // heuristic and k_m, hence the factor).
  if (static_cast<int64_t>(blocked_.size()) * 4 > OctileCost::kMaxCells)
    throw Error(ErrorCode::kInvalidArgument, "map: " + std::to_string(width_) + " x " + std::to_string(height_) +
                                                 " cells is too large for D* Lite's exact costs");
  node_[Index(goal)].rhs = OctileCost{};
  Push(Index(goal), goal.x, goal.y);
}

DStarLite::Key DStarLite::CalculateKey(int32_t s, int x, int y) const {
  const OctileCost m = Min(node_[s].g, node_[s].rhs);
  return {m + HeuristicToStart(x, y) + km_, m};
}

void DStarLite::Push(int32_t u, int x, int y) {
  const Key k = CalculateKey(u, x, y);
  node_[u].queued_key = k;
  node_[u].in_queue = true;
  heap_.push(k, u);
}

template <typename F>
void DStarLite::ForEachEdge(int32_t u, int x, int y, F&& f) const {
  if (!Free(x, y)) return;  // a blocked cell has no traversable edges
  ForEachMove(
      x, y, [this](int cx, int cy) { return Free(cx, cy); },
      [&](int nx, int ny, bool diagonal) { f(ny * width_ + nx, nx, ny, diagonal ? kDiagonal : kStraight); });
}

void DStarLite::RecomputeRhs(int32_t u) {
  if (u == Index(goal_)) return;
  OctileCost best = kInf;
  ForEachEdge(u, [&](int32_t s, int, int, const OctileCost& c) { best = Min(best, c + node_[s].g); });
  node_[u].rhs = best;
}

void DStarLite::UpdateQueue(int32_t u, int x, int y) {
  if (node_[u].g == node_[u].rhs) {
    node_[u].in_queue = false;  // consistent: any queued entry is stale
  } else if (!node_[u].in_queue || !(node_[u].queued_key == CalculateKey(u, x, y))) {
    Push(u, x, y);
  }
}

void DStarLite::UpdateVertex(int32_t u) {
  RecomputeRhs(u);
  UpdateQueue(u);
}

bool DStarLite::ComputeShortestPath(const StopRequested& stop) {
  const int32_t s_start = Index(start_);
  while (!heap_.empty()) {
    const auto top = heap_.top();
    if (!node_[top.node].in_queue || !(node_[top.node].queued_key == top.key)) {  // stale entry
      heap_.pop();
      continue;
    }
    // Stop once nothing queued can lower the start's cost (exact comparison: see OctileCost).
    if (!(top.key < CalculateKey(s_start)) && node_[s_start].rhs == node_[s_start].g) break;
    CountExpansion(expansions_, stop);
    const int32_t u = top.node;
    const int ux = u % width_, uy = u / width_;
    const Key k_new = CalculateKey(u, ux, uy);
    heap_.pop();
    node_[u].in_queue = false;
    if (top.key < k_new) {
      Push(u, ux, uy);  // its key rose since it was queued (k_m grew): requeue
    } else if (node_[u].rhs < node_[u].g) {
      // Overconsistent: settle it; neighbours can only improve through it (the paper's optimised
      // version: an O(1) min instead of recomputing their rhs).
      node_[u].g = node_[u].rhs;
      const int32_t goal = Index(goal_);
      ForEachEdge(u, ux, uy, [&](int32_t s, int sx, int sy, const OctileCost& c) {
        if (s != goal) node_[s].rhs = Min(node_[s].rhs, c + node_[u].g);
        UpdateQueue(s, sx, sy);
      });
    } else {
      // Underconsistent: raise it; only neighbours whose rhs came through it need recomputing.
      const OctileCost g_old = node_[u].g;
      node_[u].g = kInf;
      ForEachEdge(u, ux, uy, [&](int32_t s, int sx, int sy, const OctileCost& c) {
        if (node_[s].rhs == c + g_old) RecomputeRhs(s);
        UpdateQueue(s, sx, sy);
      });
      UpdateVertex(u);
    }
  }
  return !node_[s_start].g.infinite();
}

void DStarLite::SetBlocked(const CellIndex& cell, bool blocked) {
  const int32_t c = Index(cell);
  if (blocked_[c] == static_cast<uint8_t>(blocked)) return;
  // Edges that change: those of the cell itself and the diagonals that squeeze past its corners,
  // all of which start at the cell or one of its 8 neighbours. Their rhs values are recomputed.
  blocked_[c] = blocked;
  if (blocked) node_[c].g = kInf;
  UpdateVertex(c);
  for (const GridMove& m : kGridMoves) {
    const int nx = cell.x + m.dx, ny = cell.y + m.dy;
    if (nx >= 0 && ny >= 0 && nx < width_ && ny < height_) UpdateVertex(ny * width_ + nx);
  }
}

void DStarLite::MoveStart(const CellIndex& start) {
  km_ = km_ + OctileCost::Distance(last_.x - start.x, last_.y - start.y);
  last_ = start;
  start_ = start;
}

std::vector<CellIndex> DStarLite::Path() const {
  std::vector<CellIndex> path;
  int32_t s = Index(start_);
  if (node_[s].g.infinite()) return path;
  const int32_t goal = Index(goal_);
  path.push_back(start_);
  // Descend g: each step to the neighbour minimising c + g (at most one step per cell).
  for (size_t steps = 0; s != goal && steps < blocked_.size(); ++steps) {
    OctileCost best = kInf;
    int32_t next = -1;
    ForEachEdge(s, [&](int32_t n, int, int, const OctileCost& c) {
      if (c + node_[n].g < best) {
        best = c + node_[n].g;
        next = n;
      }
    });
    if (next < 0) return {};
    s = next;
    path.push_back(Cell(s));
  }
  return s == goal ? path : std::vector<CellIndex>{};
}

CellPath DStarLitePlanner::Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                                const PlannerOptions&, const StopRequested& stop) const {
  DStarLite search(costmap, start, goal);
  CellPath result;
  if (search.ComputeShortestPath(stop)) result.cells = search.Path();
  result.expansions = search.expansions();
  return result;
}

}  // namespace navd::planning
