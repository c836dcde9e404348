#include "services/localization/global_scan_search.h"

#include <algorithm>
#include <cmath>

#include "services/common/grid_traversal.h"

namespace navd::localization {

namespace {

// Sliding maximum over [i - half, i + half] along one axis of a width x height grid.
std::vector<float> SlidingMax(const std::vector<float>& in, int width, int height, int half, bool along_x) {
  std::vector<float> out(in.size());
  const int n = along_x ? width : height, lines = along_x ? height : width;
  for (int line = 0; line < lines; ++line) {
    auto at = [&](int i) -> size_t {
      return along_x ? static_cast<size_t>(line) * width + i : static_cast<size_t>(i) * width + line;
    };
    for (int i = 0; i < n; ++i) {
      float best = 0.0f;
      for (int j = std::max(0, i - half); j <= std::min(n - 1, i + half); ++j) best = std::max(best, in[at(j)]);
      out[at(i)] = best;
    }
  }
  return out;
}

}  // namespace

GlobalScanSearch::GlobalScanSearch(const OccupancyGrid& map, const LikelihoodField& field,
                                   const GlobalScanSearchOptions& options)
    : o_(options),
      map_(map),
      field_(field),
      width_(map.width()),
      height_(map.height()),
      resolution_(map.resolution()),
      origin_(map.origin()) {
  block_cells_ = std::max(1, static_cast<int>(std::lround(o_.block / resolution_)));
  const float best = static_cast<float>(field.best_log_likelihood());
  std::vector<float> score(static_cast<size_t>(width_) * height_);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      score[static_cast<size_t>(y) * width_ + x] =
          std::exp(field.LogLikelihoodAtCell(static_cast<float>(x), static_cast<float>(y)) - best);
  // Half a block, and a cell for the rounding of the point's cell.
  const int half = block_cells_ / 2 + 1;
  bound_ = SlidingMax(SlidingMax(score, width_, height_, half, true), width_, height_, half, false);
  for (int by = 0; by * block_cells_ < height_; ++by) {
    for (int bx = 0; bx * block_cells_ < width_; ++bx) {
      bool free = false;
      for (int y = by * block_cells_; y < std::min(height_, (by + 1) * block_cells_) && !free; ++y)
        for (int x = bx * block_cells_; x < std::min(width_, (bx + 1) * block_cells_) && !free; ++x)
          free = OccupancyGrid::IsFreeValue(map.cells()[static_cast<size_t>(y) * width_ + x]);
      if (free) {
        blocks_.emplace_back(origin_ + resolution_ * Point2(bx * block_cells_ + 0.5 * block_cells_,
                                                            by * block_cells_ + 0.5 * block_cells_));
      }
    }
  }
}

std::vector<Point2> GlobalScanSearch::Scored(const std::vector<Point2>& all_points) const {
  std::vector<Point2> points;
  for (const Point2& p : all_points)
    if (p.allFinite() && p.norm() <= o_.max_range) points.push_back(p);
  if (points.size() > static_cast<size_t>(o_.points)) {
    std::vector<Point2> thinned;
    thinned.reserve(o_.points);
    for (int i = 0; i < o_.points; ++i) thinned.push_back(points[i * points.size() / o_.points]);
    points.swap(thinned);
  }
  return points;
}

double GlobalScanSearch::Score(const Pose2& pose, const std::vector<Point2>& all_points) const {
  const std::vector<Point2> points = Scored(all_points);
  return points.empty() ? 0.0 : field_.Agreement(pose, points);
}

std::vector<PoseCandidate> GlobalScanSearch::Search(const std::vector<Point2>& all_points,
                                                    const SearchWindow* window) const {
  const std::vector<Point2> points = Scored(all_points);
  if (points.size() < 5 || blocks_.empty()) return {};

  // Coarse: every block and heading (in the window, if any) against the bound, in cells.
  const int headings = std::max(1, static_cast<int>(std::lround(2.0 * M_PI / o_.angle_step)));
  std::vector<int> searched_blocks;
  for (size_t b = 0; b < blocks_.size(); ++b)
    if (!window || (blocks_[b] - window->centre.translation()).norm() <= window->radius)
      searched_blocks.push_back(static_cast<int>(b));
  struct Coarse {
    float score;
    int block, heading;
  };
  std::vector<Coarse> coarse;
  coarse.reserve(blocks_.size() * headings);
  std::vector<float> rx(points.size()), ry(points.size());
  const double inv = 1.0 / resolution_;
  for (int h = 0; h < headings; ++h) {
    const double theta = h * 2.0 * M_PI / headings, c = std::cos(theta), s = std::sin(theta);
    if (window && std::abs(NormalizeAngle(theta - window->centre.theta)) > window->max_turn + 0.5 * o_.angle_step)
      continue;
    for (size_t j = 0; j < points.size(); ++j) {
      rx[j] = static_cast<float>((c * points[j].x() - s * points[j].y()) * inv);
      ry[j] = static_cast<float>((s * points[j].x() + c * points[j].y()) * inv);
    }
    for (const int b : searched_blocks) {
      const float cx = static_cast<float>((blocks_[b].x() - origin_.x()) * inv - 0.5);
      const float cy = static_cast<float>((blocks_[b].y() - origin_.y()) * inv - 0.5);
      float sum = 0.0f;
      for (size_t j = 0; j < points.size(); ++j) {
        const int x = static_cast<int>(std::lround(cx + rx[j])), y = static_cast<int>(std::lround(cy + ry[j]));
        if (x >= 0 && y >= 0 && x < width_ && y < height_) sum += bound_[static_cast<size_t>(y) * width_ + x];
      }
      coarse.push_back({sum / points.size(), b, h});
    }
  }
  if (coarse.empty()) return {};
  const size_t keep =
      std::min(coarse.size(), static_cast<size_t>(std::max(1, window ? window->blocks_refined : o_.blocks_refined)));
  std::nth_element(coarse.begin(), coarse.begin() + (keep - 1), coarse.end(),
                   [](const Coarse& a, const Coarse& b) { return a.score > b.score; });
  coarse.resize(keep);

  // Fine: cell by cell within each kept block, quarter heading steps around its heading.
  std::vector<PoseCandidate> fine;
  const int step = std::max(1, block_cells_ / 3);
  for (const Coarse& k : coarse) {
    PoseCandidate best;
    for (int dy = -block_cells_ / 2; dy <= block_cells_ / 2; dy += step) {
      for (int dx = -block_cells_ / 2; dx <= block_cells_ / 2; dx += step) {
        for (int q = -2; q <= 2; ++q) {
          const Pose2 pose{blocks_[k.block].x() + dx * resolution_, blocks_[k.block].y() + dy * resolution_,
                           NormalizeAngle(k.heading * 2.0 * M_PI / headings + q * 0.25 * 2.0 * M_PI / headings)};
          const double score = field_.Agreement(pose, points);
          if (score > best.score) best = {pose, score};
        }
      }
    }
    fine.push_back(best);
  }
  std::sort(fine.begin(), fine.end(), [](const PoseCandidate& a, const PoseCandidate& b) { return a.score > b.score; });
  std::vector<PoseCandidate> distinct;
  for (const PoseCandidate& c : fine) {
    if (distinct.size() >= static_cast<size_t>(o_.candidates)) break;
    const bool seen = std::any_of(distinct.begin(), distinct.end(), [&](const PoseCandidate& d) {
      return std::hypot(d.pose.x - c.pose.x, d.pose.y - c.pose.y) < o_.distinct_xy &&
             std::abs(NormalizeAngle(d.pose.theta - c.pose.theta)) < o_.distinct_theta;
    });
    if (!seen) distinct.push_back(c);
  }
  return distinct;
}

double GlobalScanSearch::SeeThrough(const Pose2& pose, const std::vector<Point2>& points, double margin) const {
  int counted = 0, through = 0;
  for (const Point2& p : points) {
    const double range = p.norm();
    if (!p.allFinite() || range <= margin) continue;
    ++counted;
    const Point2 end = pose * (p * ((range - margin) / range));
    const bool clear = TraverseSegment(map_, pose.translation(), end, [&](const CellIndex& c, double) {
      return !map_.Contains(c) || !map_.IsOccupied(c);
    });
    through += clear ? 0 : 1;
  }
  return counted > 0 ? static_cast<double>(through) / counted : 0.0;
}

}  // namespace navd::localization
