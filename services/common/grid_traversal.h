#pragma once
// Exact traversal of the grid cells a segment passes through (Amanatides & Woo, 1987), shared by
// line-of-sight checks and the simulated laser. Where the segment crosses a cell corner exactly
// (within 1e-9 of a cell), both side cells are visited too, so nothing slips between two
// diagonal obstacles. Points in metres, map frame.
#include <cmath>
#include <limits>

#include "services/common/occupancy_grid.h"

namespace navd {

// Calls visit(cell, t) for every cell along the segment from `a` to `b`, in order, where t is the
// distance from `a` (metres) at which the segment enters the cell (0 for a's own cell). Stops early
// and returns false as soon as visit returns false; returns true when the whole segment was visited.
// Cells may lie outside the grid; the visitor decides what that means.
template <typename Visit>
bool TraverseSegment(const OccupancyGrid& grid, const Point2& a, const Point2& b, Visit&& visit) {
  const double res = grid.resolution();
  const Point2 d = b - a;
  const double length = d.norm();
  CellIndex c = grid.CellOf(a);
  if (!visit(c, 0.0)) return false;
  if (length == 0.0) return true;
  const Point2 dir = d / length;
  const CellIndex last = grid.CellOf(b);
  const int step_x = dir.x() > 0 ? 1 : -1, step_y = dir.y() > 0 ? 1 : -1;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Distance along the segment to the next vertical / horizontal cell boundary, and per cell.
  const Point2 local = (a - grid.origin()) / res;
  const double next_x = dir.x() > 0 ? std::floor(local.x()) + 1 : std::floor(local.x());
  const double next_y = dir.y() > 0 ? std::floor(local.y()) + 1 : std::floor(local.y());
  double t_x = dir.x() != 0 ? (next_x - local.x()) * res / dir.x() : kInf;
  double t_y = dir.y() != 0 ? (next_y - local.y()) * res / dir.y() : kInf;
  const double dt_x = dir.x() != 0 ? res / std::abs(dir.x()) : kInf;
  const double dt_y = dir.y() != 0 ? res / std::abs(dir.y()) : kInf;
  const double corner_tolerance = 1e-9 * res;
  // The cell count bounds the loop even if rounding keeps `last` from being hit exactly.
  int remaining = std::abs(last.x - c.x) + std::abs(last.y - c.y);
  while (remaining > 0) {
    if (std::abs(t_x - t_y) <= corner_tolerance) {
      const double t = std::min(t_x, t_y);
      if (t > length) break;
      if (!visit(CellIndex{c.x + step_x, c.y}, t) || !visit(CellIndex{c.x, c.y + step_y}, t)) return false;
      c.x += step_x;
      c.y += step_y;
      t_x += dt_x;
      t_y += dt_y;
      remaining -= 2;
      if (!visit(c, t)) return false;
    } else if (t_x < t_y) {
      if (t_x > length) break;
      c.x += step_x;
      --remaining;
      if (!visit(c, t_x)) return false;
      t_x += dt_x;
    } else {
      if (t_y > length) break;
      c.y += step_y;
      --remaining;
      if (!visit(c, t_y)) return false;
      t_y += dt_y;
    }
  }
  return true;
}

}  // namespace navd
