#pragma once
// The moves of navd's grid planners, in one place: 4 straight moves (cost 1 cell) and 4 diagonal
// ones (cost sqrt 2), where a diagonal move needs both side cells free, so no path squeezes
// between two obstacles that touch at a corner (MovingAI's "no corner cutting").
#include <cmath>

namespace navd::planning {

struct GridMove {
  int dx, dy;
  bool diagonal;
};

// Straight moves first: the first 4 entries are the 4-connected neighbourhood.
inline constexpr GridMove kGridMoves[8] = {{1, 0, false}, {-1, 0, false}, {0, 1, false}, {0, -1, false},
                                           {1, 1, true},  {1, -1, true},  {-1, 1, true}, {-1, -1, true}};

// The grid distance in cells between cells dx, dy apart (octile, or Manhattan for 4-connected
// moves), inflated by 1e-9: as an A* heuristic it breaks the vast ties of octile distance towards
// the goal (far fewer expansions in open space) without costing optimality, since for paths under
// ~1e4 cells 1e-9 of the length is below the smallest gap between two distinct path lengths.
inline double TieBreakingDistance(int dx, int dy, bool diagonal) {
  const double ax = dx < 0 ? -dx : dx, ay = dy < 0 ? -dy : dy;
  return (1.0 + 1e-9) * (diagonal ? (ax + ay) + (M_SQRT2 - 2.0) * (ax < ay ? ax : ay) : ax + ay);
}

// Calls visit(nx, ny, diagonal) for each of the first `Moves` (4 or 8) moves from (x, y) that
// `free(x, y)` allows. A compile-time count lets the compiler unroll the loop in search hot paths.
template <int Moves = 8, typename Free, typename Visit>
inline void ForEachMove(int x, int y, const Free& free, const Visit& visit) {
  static_assert(Moves == 4 || Moves == 8);
  for (int k = 0; k < Moves; ++k) {
    const GridMove& m = kGridMoves[k];
    const int nx = x + m.dx, ny = y + m.dy;
    if (!free(nx, ny)) continue;
    if (m.diagonal && (!free(x + m.dx, y) || !free(x, y + m.dy))) continue;
    visit(nx, ny, m.diagonal);
  }
}

}  // namespace navd::planning
