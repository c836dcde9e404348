#include "services/planning/grid_astar_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>

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
  return {
      {"diagonal", 1.0, "1: 8-connected moves, 0: 4-connected"},
      {"cost_weight", 1.0, "step cost = length * (1 + cost_weight * cost / 252) on the costmap's decay layer (>= 0)"}};
}

namespace {

// Step costs as lengths, in doubles: exact shortest paths on grids without a cost layer.
// Distinct 8-connected path lengths a + b*sqrt(2) can differ by ~1e-5 on large maps, below float
// resolution, so g is a double.
class LengthCosts {
 public:
  using Value = double;
  using Heap = QuaternaryHeap<double>;

  LengthCosts(const Costmap&, const CellIndex& goal, bool diagonal, double) : goal_(goal), diagonal_(diagonal) {}
  static Value Get(const SearchWorkspace& ws, int32_t i) { return ws.g(i); }
  static void Set(SearchWorkspace& ws, int32_t i, Value g, int32_t parent) { ws.Set(i, g, parent); }
  static void Push(Heap& heap, Value key, int32_t node) { heap.push(key, node); }
  static int32_t Pop(Heap& heap) { return heap.pop().node; }
  Value Step(int k, int32_t, int32_t) const { return kGridMoves[k].diagonal ? M_SQRT2 : 1.0; }
  Value Heuristic(int x, int y) const { return TieBreakingDistance(x - goal_.x, y - goal_.y, diagonal_); }

 private:
  CellIndex goal_;
  bool diagonal_;
};

// Step costs weighed by the decay layer, length * (1 + cost_weight * mean cost of the two cells /
// kMaxCost), in fixed point: integers 2^-F of a cell, F as fine as the map's longest possible
// cost allows (at least 2^-8 of a cell per step, so a path's cost is within steps/512 cells of its
// real-valued cost). The heap packs each node into the low 25 bits of its key: 8-byte entries,
// integer comparisons. The heuristic (octile distance, rounded down) stays a lower bound.
class LayerCosts {
 public:
  using Value = int64_t;
  struct Packed {
    uint64_t key;
  };
  using Heap = QuaternaryHeap<uint64_t, Packed>;
  static constexpr int kNodeBits = 25;
  static_assert(OccupancyGrid::kMaxCells < (1ll << kNodeBits));

  LayerCosts(const Costmap& costmap, const CellIndex& goal, bool diagonal, double cost_weight)
      : cost_(costmap.cost_data()), goal_(goal), diagonal_(diagonal) {
    // Any simple path costs at most cells * sqrt(2) * (1 + cost_weight); keys have 64 - 25 bits.
    const double cells = static_cast<double>(costmap.width()) * costmap.height();
    const int bits = 64 - kNodeBits - 1 - static_cast<int>(std::ceil(std::log2(cells * M_SQRT2 * (1.0 + cost_weight))));
    if (bits < 8) {
      throw Error(ErrorCode::kInvalidArgument, "options: 'cost_weight' " + std::to_string(cost_weight) +
                                                   " is too large for a map of " +
                                                   std::to_string(static_cast<long long>(cells)) + " cells");
    }
    const double scale = std::ldexp(1.0, std::min(bits, 30));
    straight_ = static_cast<int64_t>(scale);
    diagonal_step_ = static_cast<int64_t>(std::floor(M_SQRT2 * scale));
    const double per_sum = 0.5 * cost_weight / Costmap::kMaxCost;
    for (int sum = 0; sum <= 2 * Costmap::kMaxCost; ++sum) {
      steps_[0][sum] = static_cast<int64_t>(std::llround(scale * (1.0 + per_sum * sum)));
      steps_[1][sum] =
          std::max(diagonal_step_, static_cast<int64_t>(std::llround(M_SQRT2 * scale * (1.0 + per_sum * sum))));
    }
  }
  static Value Get(const SearchWorkspace& ws, int32_t i) { return ws.cost(i); }
  static void Set(SearchWorkspace& ws, int32_t i, Value c, int32_t parent) { ws.SetCost(i, c, parent); }
  static void Push(Heap& heap, Value key, int32_t node) {
    heap.push(Packed{static_cast<uint64_t>(key) << kNodeBits | static_cast<uint32_t>(node)});
  }
  static int32_t Pop(Heap& heap) { return static_cast<int32_t>(heap.pop().key & ((1u << kNodeBits) - 1)); }
  Value Step(int k, int32_t from, int32_t to) const { return steps_[kGridMoves[k].diagonal][cost_[from] + cost_[to]]; }
  Value Heuristic(int x, int y) const {
    const int64_t dx = std::abs(x - goal_.x), dy = std::abs(y - goal_.y);
    if (!diagonal_) return (dx + dy) * straight_;
    return std::max(dx, dy) * straight_ + std::min(dx, dy) * (diagonal_step_ - straight_);
  }

 private:
  const uint8_t* cost_;
  CellIndex goal_;
  bool diagonal_;
  int64_t straight_ = 0, diagonal_step_ = 0;
  int64_t steps_[2][2 * Costmap::kMaxCost + 1];
};

// The search loop, compiled once per combination so the inner loop carries no branches on them:
// kHeuristic (A*; Dijkstra without) and how steps are costed.
template <bool kHeuristic, typename Costs>
CellPath Search(const Costmap& costmap, const CellIndex& start, const CellIndex& goal, bool diagonal,
                double cost_weight, const StopRequested& stop) {
  const int w = costmap.width();
  SearchWorkspace& ws = SearchWorkspace::ForThisThread(static_cast<size_t>(w) * costmap.height());
  const Costs costs(costmap, goal, diagonal, cost_weight);
  const uint8_t* moves = costmap.move_data();
  const unsigned allowed = diagonal ? 0xFFu : 0x0Fu;
  int32_t offset[8];
  for (int k = 0; k < 8; ++k) offset[k] = kGridMoves[k].dy * w + kGridMoves[k].dx;
  auto heuristic = [&](int x, int y) -> typename Costs::Value {
    if constexpr (!kHeuristic) return 0;
    return costs.Heuristic(x, y);
  };

  thread_local typename Costs::Heap open;
  open.clear();
  const int32_t s = static_cast<int32_t>(start.y) * w + start.x;
  const int32_t t = static_cast<int32_t>(goal.y) * w + goal.x;
  Costs::Set(ws, s, 0, -1);
  Costs::Push(open, heuristic(start.x, start.y), s);

  CellPath result;
  while (!open.empty()) {
    const int32_t current = Costs::Pop(open);
    if (ws.closed(current)) continue;  // a stale duplicate
    ws.Close(current);
    CountExpansion(result.expansions, stop);
    if (current == t) break;
    const int x = current % w, y = current / w;
    const auto g_current = Costs::Get(ws, current);
    for (unsigned m = moves[current] & allowed; m != 0; m &= m - 1) {
      const int k = __builtin_ctz(m);
      const int32_t ni = current + offset[k];
      if (ws.closed(ni)) continue;
      const auto ng = g_current + costs.Step(k, current, ni);
      if (ng < Costs::Get(ws, ni)) {
        Costs::Set(ws, ni, ng, current);
        Costs::Push(open, ng + heuristic(x + kGridMoves[k].dx, y + kGridMoves[k].dy), ni);
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
    return weigh_cost ? Search<false, LayerCosts>(costmap, start, goal, diagonal, cost_weight, stop)
                      : Search<false, LengthCosts>(costmap, start, goal, diagonal, cost_weight, stop);
  }
  return weigh_cost ? Search<true, LayerCosts>(costmap, start, goal, diagonal, cost_weight, stop)
                    : Search<true, LengthCosts>(costmap, start, goal, diagonal, cost_weight, stop);
}

}  // namespace navd::planning
