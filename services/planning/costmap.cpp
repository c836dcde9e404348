#include "services/planning/costmap.h"

#include <algorithm>
#include <cmath>
#include <queue>

#include "services/common/distance_field.h"
#include "services/common/grid_traversal.h"

namespace navd::planning {

Costmap::Costmap(std::shared_ptr<const OccupancyGrid> grid_ptr, const CostmapOptions& options)
    : grid_(std::move(grid_ptr)),
      options_(options),
      lethal_(grid_->cells().size(), 0),
      distance_(grid_->cells().size()) {
  // Distances to the nearest obstacle (exact) decide both layers: one pass, any radius.
  const DistanceField field(*grid_, options.unknown_is_lethal);
  const double lethal_within = options.inflation_radius + 1e-9;
  const double decay_until = options.inflation_radius + options.decay_radius;
  if (options.decay_radius > 0) cost_.assign(lethal_.size(), 0);
  for (size_t i = 0; i < lethal_.size(); ++i) {
    const double d = field.values()[i];
    distance_[i] = static_cast<float>(d);
    if (d <= lethal_within) {
      lethal_[i] = 1;
    } else if (d < decay_until) {
      cost_[i] = static_cast<uint8_t>(
          std::lround(kMaxCost * std::exp(-options.cost_scaling * (d - options.inflation_radius))));
    }
  }
  BuildMoveMasks();
}

void Costmap::BuildMoveMasks() {
  const int w = grid_->width(), h = grid_->height();
  moves_.assign(lethal_.size(), 0);
  // Bits in kGridMoves order: E, W, N, S, NE, SE, NW, SW; a diagonal needs both its sides.
  auto mask = [](unsigned here, unsigned e, unsigned west, unsigned n, unsigned s, unsigned ne, unsigned se,
                 unsigned nw, unsigned sw) {
    const unsigned m = e | west << 1 | n << 2 | s << 3 | (e & n & ne) << 4 | (e & s & se) << 5 | (west & n & nw) << 6 |
                       (west & s & sw) << 7;
    return static_cast<uint8_t>(here ? m : 0);
  };
  // Inner cells read their neighbours' flags directly (free = 1 - lethal), with no bounds tests.
  for (int y = 1; y + 1 < h; ++y) {
    const uint8_t* below = &lethal_[static_cast<size_t>(y - 1) * w];
    const uint8_t* here = below + w;
    const uint8_t* above = here + w;
    uint8_t* out = &moves_[static_cast<size_t>(y) * w];
    for (int x = 1; x + 1 < w; ++x) {
      out[x] = mask(here[x] ^ 1u, here[x + 1] ^ 1u, here[x - 1] ^ 1u, above[x] ^ 1u, below[x] ^ 1u, above[x + 1] ^ 1u,
                    below[x + 1] ^ 1u, above[x - 1] ^ 1u, below[x - 1] ^ 1u);
    }
  }
  // The map's edge cells, whose outside neighbours count as lethal.
  auto free = [&](int x, int y) -> unsigned {
    return x >= 0 && y >= 0 && x < w && y < h && !lethal_[static_cast<size_t>(y) * w + x];
  };
  auto edge = [&](int x, int y) {
    moves_[static_cast<size_t>(y) * w + x] =
        mask(free(x, y), free(x + 1, y), free(x - 1, y), free(x, y + 1), free(x, y - 1), free(x + 1, y + 1),
             free(x + 1, y - 1), free(x - 1, y + 1), free(x - 1, y - 1));
  };
  for (int x = 0; x < w; ++x) {
    edge(x, 0);
    edge(x, h - 1);
  }
  for (int y = 0; y < h; ++y) {
    edge(0, y);
    edge(w - 1, y);
  }
}

bool Costmap::SegmentFree(const Point2& a, const Point2& b) const {
  return TraverseSegment(*grid_, a, b,
                         [this](const CellIndex& c, double) { return grid_->Contains(c) && !IsLethal(c); });
}

int Costmap::SegmentMaxCost(const Point2& a, const Point2& b) const {
  int worst = 0;
  const bool free = TraverseSegment(*grid_, a, b, [&](const CellIndex& c, double) {
    if (!grid_->Contains(c) || IsLethal(c)) return false;
    if (!cost_.empty()) worst = std::max<int>(worst, cost_[grid_->Flat(c)]);
    return true;
  });
  return free ? worst : -1;
}

std::optional<CellIndex> Costmap::NearestFree(const CellIndex& from, int max_cells, bool through_obstacles) const {
  if (!grid_->Contains(from)) return std::nullopt;
  if (!IsLethal(from)) return from;
  // Marks over the search window only: the executive asks every control step.
  const int side = 2 * max_cells + 1;
  std::vector<uint8_t> seen(static_cast<size_t>(side) * side, 0);
  auto mark = [&](const CellIndex& c) -> uint8_t& {
    return seen[static_cast<size_t>(c.y - from.y + max_cells) * side + (c.x - from.x + max_cells)];
  };
  std::queue<CellIndex> q;
  q.push(from);
  mark(from) = 1;
  while (!q.empty()) {
    const CellIndex c = q.front();
    q.pop();
    for (const CellIndex d : {CellIndex{1, 0}, CellIndex{-1, 0}, CellIndex{0, 1}, CellIndex{0, -1}}) {
      const CellIndex n{c.x + d.x, c.y + d.y};
      if (!grid_->Contains(n) || std::abs(n.x - from.x) > max_cells || std::abs(n.y - from.y) > max_cells || mark(n) ||
          (!through_obstacles && grid_->IsOccupied(n))) {
        continue;
      }
      mark(n) = 1;
      if (!IsLethal(n)) return n;
      q.push(n);
    }
  }
  return std::nullopt;
}

}  // namespace navd::planning
