#include "services/mapping/map_coverage.h"

#include <queue>

namespace navd::mapping {

MapCoverage CoverageOf(const OccupancyGrid& built, const OccupancyGrid& truth, const Point2& start, int free_below) {
  MapCoverage out;
  const CellIndex s = truth.CellOf(start);
  if (!truth.Contains(s) || truth.at(s) != OccupancyGrid::kFree) return out;
  std::vector<uint8_t> seen(truth.cells().size(), 0);
  std::queue<CellIndex> q;
  q.push(s);
  seen[truth.Flat(s)] = 1;
  size_t known = 0, known_free = 0;
  while (!q.empty()) {
    const CellIndex c = q.front();
    q.pop();
    ++out.reachable_cells;
    const CellIndex b = built.CellOf(truth.CellCenter(c));
    if (built.Contains(b) && built.at(b) >= 0) {
      ++known;
      known_free += built.at(b) < free_below;
    }
    for (const CellIndex d : {CellIndex{1, 0}, CellIndex{-1, 0}, CellIndex{0, 1}, CellIndex{0, -1}}) {
      const CellIndex n{c.x + d.x, c.y + d.y};
      if (!truth.Contains(n) || seen[truth.Flat(n)] || truth.at(n) != OccupancyGrid::kFree) continue;
      seen[truth.Flat(n)] = 1;
      q.push(n);
    }
  }
  out.known = static_cast<double>(known) / static_cast<double>(out.reachable_cells);
  out.known_free = static_cast<double>(known_free) / static_cast<double>(out.reachable_cells);
  return out;
}

}  // namespace navd::mapping
