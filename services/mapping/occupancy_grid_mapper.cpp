#include "services/mapping/occupancy_grid_mapper.h"

#include <algorithm>
#include <cmath>

#include "services/common/error.h"
#include "services/common/grid_traversal.h"

namespace navd::mapping {

OccupancyGridMapper::OccupancyGridMapper(const Point2& min, const Point2& max, const MapperOptions& options)
    : o_(options) {
  const long long w = static_cast<long long>(std::ceil((max.x() - min.x()) / options.resolution));
  const long long h = static_cast<long long>(std::ceil((max.y() - min.y()) / options.resolution));
  if (w < 1 || h < 1 || w * h > OccupancyGrid::kMaxCells) {
    throw Error(ErrorCode::kInvalidArgument, "map extent must span 1 to " + std::to_string(OccupancyGrid::kMaxCells) +
                                                 " cells at this resolution");
  }
  geometry_ = OccupancyGrid(static_cast<int>(w), static_cast<int>(h), options.resolution, min, OccupancyGrid::kUnknown);
  log_odds_.assign(static_cast<size_t>(w) * h, 0.0f);
  seen_.assign(log_odds_.size(), 0);
}

void OccupancyGridMapper::AddScan(const Pose2& pose, const std::vector<float>& ranges, double angle_min,
                                  double increment) {
  for (size_t i = 0; i < ranges.size(); ++i) {
    const double r = ranges[i];
    if (!std::isfinite(r) || r <= 0.0) continue;
    const bool hit = r < o_.max_range && r <= o_.usable_range;
    const double length = std::min(r, o_.usable_range);
    const double a = pose.theta + angle_min + i * increment;
    const Point2 from = pose.translation();
    const Point2 dir(std::cos(a), std::sin(a));
    const Point2 to = from + length * dir;
    // A reading measures the distance to a surface; a hair further along the beam is the cell
    // behind it (a reading ending exactly on a cell border would otherwise mark the free cell).
    const CellIndex end = geometry_.CellOf(to + 0.01 * geometry_.resolution() * dir);
    TraverseSegment(geometry_, from, to, [&](const CellIndex& c, double) {
      if (!geometry_.Contains(c)) return true;
      if (hit && c == end) return true;  // the end cell is updated below
      const size_t k = geometry_.Flat(c);
      log_odds_[k] = std::max(static_cast<float>(o_.l_min), log_odds_[k] + static_cast<float>(o_.l_free));
      seen_[k] = 1;
      return true;
    });
    if (hit && geometry_.Contains(end)) {
      const size_t k = geometry_.Flat(end);
      log_odds_[k] = std::min(static_cast<float>(o_.l_max), log_odds_[k] + static_cast<float>(o_.l_occupied));
      seen_[k] = 1;
    }
  }
}

OccupancyGrid OccupancyGridMapper::ToGrid() const {
  OccupancyGrid g = geometry_;
  for (int y = 0; y < g.height(); ++y)
    for (int x = 0; x < g.width(); ++x) {
      const size_t k = g.Flat({x, y});
      if (!seen_[k]) continue;
      const double p = 1.0 - 1.0 / (1.0 + std::exp(log_odds_[k]));
      g.set({x, y}, static_cast<int8_t>(std::lround(100.0 * p)));
    }
  return g;
}

}  // namespace navd::mapping
