#include "services/planning/jump_point_planner.h"

#include <algorithm>
#include <cmath>

#include "services/common/error.h"
#include "services/planning/grid_moves.h"
#include "services/planning/quaternary_heap.h"
#include "services/planning/search_workspace.h"

namespace navd::planning {
namespace {

constexpr unsigned Bit(int k) { return 1u << k; }
// kGridMoves indices: straight E, W, N, S = 0..3; diagonals NE, SE, NW, SW = 4..7.
constexpr int kEast = 0, kWest = 1, kNorth = 2, kSouth = 3;
constexpr unsigned kEastWest = Bit(kEast) | Bit(kWest), kNorthSouth = Bit(kNorth) | Bit(kSouth);

// The kGridMoves index of the move (dx, dy), each -1, 0 or 1, not both 0.
constexpr int MoveIndex(int dx, int dy) {
  constexpr int kByDelta[9] = {7, 1, 6, 3, -1, 2, 5, 0, 4};  // [(dx + 1) * 3 + (dy + 1)]
  return kByDelta[(dx + 1) * 3 + (dy + 1)];
}
static_assert([] {
  for (int k = 0; k < 8; ++k)
    if (MoveIndex(kGridMoves[k].dx, kGridMoves[k].dy) != k) return false;
  return true;
}());

// The runs of one search, on flat cell indices and the costmap's move masks.
class Runs {
 public:
  Runs(const Costmap& costmap, int32_t goal) : moves_(costmap.move_data()), goal_(goal) {
    for (int k = 0; k < 8; ++k) offset_[k] = kGridMoves[k].dy * costmap.width() + kGridMoves[k].dx;
  }
  int32_t offset(int k) const { return offset_[k]; }
  unsigned moves(int32_t cell) const { return moves_[cell]; }

  // Whether side `side` (a straight move across straight move k) is forced at `cell`, reached by
  // move k: the side cell beside the previous cell is blocked and the one beside `cell` is open.
  bool Forced(int32_t cell, int k, int side) const {
    return (~moves_[cell - offset_[k]] & moves_[cell] & Bit(side)) != 0;
  }

  // The jump point of a straight run from `from` by move k (0..3), or -1 when the run hits a wall.
  int32_t Straight(int32_t from, int k) const {
    const unsigned sides = k < 2 ? kNorthSouth : kEastWest;
    int32_t c = from;
    unsigned mc = moves_[c];
    while (mc & Bit(k)) {
      const int32_t n = c + offset_[k];
      const unsigned mn = moves_[n];
      if (n == goal_ || (~mc & mn & sides) != 0) return n;
      c = n;
      mc = mn;
    }
    return -1;
  }

  // The jump point of a diagonal run from `from` by move k (4..7): the first cell that is the goal
  // or from which a straight run along either component finds a jump point; -1 at a wall.
  int32_t Diagonal(int32_t from, int k, int kx, int ky) const {
    int32_t c = from;
    while (moves_[c] & Bit(k)) {
      c += offset_[k];
      if (c == goal_ || Straight(c, kx) >= 0 || Straight(c, ky) >= 0) return c;
    }
    return -1;
  }

 private:
  const uint8_t* moves_;
  int32_t goal_;
  int32_t offset_[8];
};

}  // namespace

std::string JumpPointPlanner::description() const {
  return "Jump Point Search: A* that expands only jump points; shortest 8-connected paths (as astar) "
         "without corner cutting, far fewer expansions; ignores the decay layer's costs";
}

CellPath JumpPointPlanner::Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                                const PlannerOptions& /*options*/, const StopRequested& stop) const {
  const int w = costmap.width();
  SearchWorkspace& ws = SearchWorkspace::ForThisThread(static_cast<size_t>(w) * costmap.height());
  const int32_t s = start.y * w + start.x, t = goal.y * w + goal.x;
  const Runs runs(costmap, t);
  auto heuristic = [&](int x, int y) { return TieBreakingDistance(x - goal.x, y - goal.y, true); };
  thread_local QuaternaryHeap<> open;
  open.clear();
  ws.Set(s, 0.0, -1);
  open.push(heuristic(start.x, start.y), s);

  CellPath result;
  while (!open.empty()) {
    const int32_t current = open.pop().node;
    if (ws.closed(current)) continue;
    ws.Close(current);
    CountExpansion(result.expansions, stop);
    if (current == t) break;
    const int x = current % w, y = current / w;
    // The directions worth running from here: all from the start; else the way we came, and from
    // a diagonal its two components, and from a straight run each forced side and the diagonal
    // towards it.
    unsigned directions = runs.moves(current);
    const int32_t parent = ws.parent(current);
    if (parent >= 0) {
      const int px = parent % w, py = parent / w;
      const int dx = (x > px) - (x < px), dy = (y > py) - (y < py);
      const int k = MoveIndex(dx, dy);
      unsigned wanted = Bit(k);
      if (dx != 0 && dy != 0) {
        wanted |= Bit(MoveIndex(dx, 0)) | Bit(MoveIndex(0, dy));
      } else {
        for (int side : {dx != 0 ? kNorth : kEast, dx != 0 ? kSouth : kWest}) {
          if (!runs.Forced(current, k, side)) continue;
          const GridMove& m = kGridMoves[side];
          wanted |= Bit(side) | Bit(MoveIndex(dx != 0 ? dx : m.dx, dy != 0 ? dy : m.dy));
        }
      }
      directions &= wanted;
    }
    const double g = ws.g(current);
    for (unsigned d = directions; d != 0; d &= d - 1) {
      const int k = __builtin_ctz(d);
      const GridMove& m = kGridMoves[k];
      const int32_t jump =
          m.diagonal ? runs.Diagonal(current, k, MoveIndex(m.dx, 0), MoveIndex(0, m.dy)) : runs.Straight(current, k);
      if (jump < 0 || ws.closed(jump)) continue;
      const int jx = jump % w, jy = jump / w;
      const int steps = std::max(std::abs(jx - x), std::abs(jy - y));
      const double ng = g + steps * (m.diagonal ? M_SQRT2 : 1.0);
      if (ng < ws.g(jump)) {
        ws.Set(jump, ng, current);
        open.push(ng + heuristic(jx, jy), jump);
      }
    }
  }
  if (!ws.closed(t)) return result;
  // Jump points are joined by straight or diagonal runs: fill in the cells between them.
  for (int32_t i = t; ws.parent(i) != -1; i = ws.parent(i)) {
    const int32_t p = ws.parent(i);
    const int x = i % w, y = i / w, px = p % w, py = p / w;
    const int dx = (x > px) - (x < px), dy = (y > py) - (y < py);
    for (int cx = x, cy = y; cx != px || cy != py; cx -= dx, cy -= dy) result.cells.push_back({cx, cy});
  }
  result.cells.push_back(start);
  std::reverse(result.cells.begin(), result.cells.end());
  return result;
}

}  // namespace navd::planning
