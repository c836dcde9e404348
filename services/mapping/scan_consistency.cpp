#include "services/mapping/scan_consistency.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "services/common/error.h"
#include "services/mapping/cell_key.h"
#include "services/mapping/line_fit.h"

namespace navd::mapping {

ScanConsistency::ScanConsistency(const std::vector<Pose2>& poses, std::vector<std::vector<Point2>> returns,
                                 const ScanConsistencyOptions& options)
    : o_(options), returns_(std::move(returns)) {
  if (poses.size() != returns_.size())
    throw Error(ErrorCode::kInvalidArgument, "scan consistency: " + std::to_string(poses.size()) + " poses for " +
                                                 std::to_string(returns_.size()) + " scans");
  // Bucketed by cells of half the neighbour radius, a return's neighbours lie in the 5 x 5 cells
  // around its own (a third fewer returns to look at than 3 x 3 cells of the radius). Each cell's
  // returns lie side by side in placed_, in scan order, the cells in key order: a dense log puts
  // thousands of returns in a cell, and visiting them in memory order, not scattered, is most of the
  // measure's speed. Counted first, then placed: no second copy of the returns.
  auto key_of = [&](const Point2& point) { return CellKey(Cell(point.x()), Cell(point.y())); };
  size_t total = 0;
  for (size_t i = 0; i < poses.size(); ++i)
    for (const Point2& p : returns_[i]) {
      ++cells_[key_of(poses[i] * p)].second;
      ++total;
    }
  std::vector<int64_t> keys;
  keys.reserve(cells_.size());
  for (const auto& [key, range] : cells_) keys.push_back(key);
  std::sort(keys.begin(), keys.end());
  int begin = 0;
  for (int64_t key : keys) {
    std::pair<int, int>& range = cells_[key];
    const int count = range.second;
    range = {begin, begin};  // second: where the cell's next return goes, its end once all are placed
    begin += count;
  }
  placed_.resize(total);
  for (size_t i = 0; i < poses.size(); ++i)
    for (const Point2& p : returns_[i]) {
      const Point2 point = poses[i] * p;
      placed_[cells_[key_of(point)].second++] = {point, static_cast<int>(i)};
    }
}

int64_t ScanConsistency::Cell(double v) const {
  return static_cast<int64_t>(std::floor(v / (o_.neighbour_radius / kCellsPerRadius)));
}

double ScanConsistency::DistanceToLine(const Point2& point, int scan) const {
  LineFit fit;
  const double r2 = o_.neighbour_radius * o_.neighbour_radius;
  const int64_t cx = Cell(point.x()), cy = Cell(point.y());
  for (int64_t dx = -kCellsPerRadius; dx <= kCellsPerRadius; ++dx)
    for (int64_t dy = -kCellsPerRadius; dy <= kCellsPerRadius; ++dy) {
      const auto found = cells_.find(CellKey(cx + dx, cy + dy));
      if (found == cells_.end()) continue;
      for (int k = found->second.first; k < found->second.second; ++k) {
        const Placed& other = placed_[k];
        if (std::abs(other.scan - scan) < o_.exclude_scans) continue;
        const Point2 d = other.point - point;
        if (d.squaredNorm() <= r2) fit.Add(d);
      }
    }
  if (fit.count() < o_.min_neighbours) return -1.0;
  const std::optional<FittedLine> line = fit.Fit(o_.max_flatness);
  if (!line) return -1.0;
  return std::min(o_.cap, std::abs(line->mean.dot(line->normal)));
}

ScanConsistencyResult ScanConsistency::Score() const {
  ScanConsistencyResult result;
  std::vector<double> scan_sum(returns_.size(), 0.0);
  result.scan_scored.assign(returns_.size(), 0);
  double sum = 0.0;
  for (const Placed& q : placed_) {
    const double distance = DistanceToLine(q.point, q.scan);
    if (distance < 0.0) continue;
    sum += distance;
    ++result.scored;
    scan_sum[q.scan] += distance;
    ++result.scan_scored[q.scan];
  }
  constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  result.mean_distance = result.scored > 0 ? sum / static_cast<double>(result.scored) : kNone;
  result.scan_mean_distance.resize(returns_.size());
  for (size_t i = 0; i < returns_.size(); ++i)
    result.scan_mean_distance[i] = result.scan_scored[i] > 0 ? scan_sum[i] / result.scan_scored[i] : kNone;
  return result;
}

ScanConsistency::ScanFit ScanConsistency::ScanAt(int k, const Pose2& pose) const {
  if (k < 0 || k >= static_cast<int>(returns_.size()))
    throw Error(ErrorCode::kInvalidArgument,
                "scan consistency: no scan " + std::to_string(k) + " of " + std::to_string(returns_.size()));
  double sum = 0.0;
  ScanFit fit;
  for (const Point2& p : returns_[k]) {
    const double distance = DistanceToLine(pose * p, k);
    if (distance < 0.0) continue;
    sum += distance;
    ++fit.scored;
  }
  fit.mean_distance = fit.scored > 0 ? sum / fit.scored : std::numeric_limits<double>::quiet_NaN();
  return fit;
}

}  // namespace navd::mapping
