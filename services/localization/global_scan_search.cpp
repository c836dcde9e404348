#include "services/localization/global_scan_search.h"

#include <algorithm>
#include <cmath>
#include <queue>

namespace navd::localization {

namespace {

// Sliding maximum over [i - half, i + half] along one axis of a width x height grid (a monotonic
// queue of candidates: linear in the cells whatever the half width).
std::vector<float> SlidingMax(const std::vector<float>& in, int width, int height, int half, bool along_x) {
  std::vector<float> out(in.size());
  const int n = along_x ? width : height, lines = along_x ? height : width;
  std::vector<int> queue(static_cast<size_t>(n));  // indices along the line, values decreasing
  for (int line = 0; line < lines; ++line) {
    auto at = [&](int i) -> size_t {
      return along_x ? static_cast<size_t>(line) * width + i : static_cast<size_t>(i) * width + line;
    };
    int head = 0, tail = 0;
    for (int i = 0; i < n + half; ++i) {
      if (i < n) {
        while (tail > head && in[at(queue[tail - 1])] <= in[at(i)]) --tail;
        queue[tail++] = i;
      }
      const int centre = i - half;
      if (centre < 0) continue;
      while (queue[head] < centre - half) ++head;
      out[at(centre)] = in[at(queue[head])];
    }
  }
  return out;
}

}  // namespace

GlobalScanSearch::GlobalScanSearch(const OccupancyGrid& map, const LikelihoodField& field,
                                   const GlobalScanSearchOptions& options)
    : o_(options),
      field_(field),
      width_(map.width()),
      height_(map.height()),
      resolution_(map.resolution()),
      origin_(map.origin()) {
  const int finest = std::max(1, static_cast<int>(std::lround(o_.block / resolution_)));
  const float best = static_cast<float>(field.best_log_likelihood());
  std::vector<float>& score = score_;
  score.resize(static_cast<size_t>(width_) * height_);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      score[static_cast<size_t>(y) * width_ + x] =
          std::exp(field.LogLikelihoodAtCell(static_cast<float>(x), static_cast<float>(y)) - best);
  for (int k = 0; k < std::max(1, o_.pyramid_levels); ++k) {
    Level level;
    level.cells = finest << k;
    level.blocks_x = (width_ + level.cells - 1) / level.cells;
    level.blocks_y = (height_ + level.cells - 1) / level.cells;
    // The finest blocks pool over half a block and a cell for the rounding of a point's cell.
    // A coarser block's pose lies within half its width (less half a finest block) of every finest
    // pose inside it; with the roundings of both, half its width and two cells bound them all.
    level.half = k == 0 ? level.cells / 2 + 1 : (level.cells + 1) / 2 + 2;
    level.clamp = k > 0;
    level.bound = SlidingMax(SlidingMax(score, width_, height_, level.half, true), width_, height_, level.half, false);
    level.free.assign(static_cast<size_t>(level.blocks_x) * level.blocks_y, 0);
    if (k == 0) {
      for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x)
          if (map.cells()[static_cast<size_t>(y) * width_ + x] == OccupancyGrid::kFree)
            level.free[static_cast<size_t>(y / level.cells) * level.blocks_x + x / level.cells] = 1;
    } else {
      const Level& finer = levels_.back();
      for (int by = 0; by < finer.blocks_y; ++by)
        for (int bx = 0; bx < finer.blocks_x; ++bx)
          if (finer.free[static_cast<size_t>(by) * finer.blocks_x + bx])
            level.free[static_cast<size_t>(by / 2) * level.blocks_x + bx / 2] = 1;
    }
    levels_.push_back(std::move(level));
  }
}

float GlobalScanSearch::BlockScore(const Level& level, int bx, int by, const float* rx, const float* ry,
                                   size_t n) const {
  // The block's centre in cells (cell centres at whole numbers).
  const float cx = bx * level.cells + 0.5f * level.cells - 0.5f, cy = by * level.cells + 0.5f * level.cells - 0.5f;
  float sum = 0.0f;
  for (size_t j = 0; j < n; ++j) {
    int x = static_cast<int>(std::lround(cx + rx[j])), y = static_cast<int>(std::lround(cy + ry[j]));
    if (level.clamp) {
      // Off the map but within the pooling of its edge: the map's part of this cell's window lies
      // within the window of the nearest edge cell.
      if (x < -level.half || y < -level.half || x >= width_ + level.half || y >= height_ + level.half) continue;
      x = std::clamp(x, 0, width_ - 1);
      y = std::clamp(y, 0, height_ - 1);
    }
    if (x >= 0 && y >= 0 && x < width_ && y < height_) sum += level.bound[static_cast<size_t>(y) * width_ + x];
  }
  return sum / static_cast<float>(n);
}

std::vector<PoseCandidate> GlobalScanSearch::Search(const std::vector<Point2>& all_points) const {
  std::vector<Point2> points;
  for (const Point2& p : all_points)
    if (p.allFinite() && p.norm() <= o_.max_range) points.push_back(p);
  if (points.size() > static_cast<size_t>(o_.points)) {
    std::vector<Point2> thinned;
    for (int i = 0; i < o_.points; ++i) thinned.push_back(points[i * points.size() / o_.points]);
    points.swap(thinned);
  }
  last_block_scores_ = 0;
  if (points.size() < 5) return {};

  // The scan's points rotated by every heading, in cells.
  const int headings = std::max(1, static_cast<int>(std::lround(2.0 * M_PI / o_.angle_step)));
  const size_t n = points.size();
  std::vector<float> rx(headings * n), ry(headings * n);
  const double inv = 1.0 / resolution_;
  for (int h = 0; h < headings; ++h) {
    const double theta = h * 2.0 * M_PI / headings, c = std::cos(theta), s = std::sin(theta);
    for (size_t j = 0; j < n; ++j) {
      rx[h * n + j] = static_cast<float>((c * points[j].x() - s * points[j].y()) * inv);
      ry[h * n + j] = static_cast<float>((s * points[j].x() + c * points[j].y()) * inv);
    }
  }

  // Best first down the pyramid: a block's score bounds its children's, so the finest blocks come
  // out in the order of their own scores, and the first blocks_refined are the best of all.
  struct Node {
    float score;
    int level, bx, by, heading;
    bool operator<(const Node& other) const { return score < other.score; }
  };
  std::priority_queue<Node> open;
  auto push = [&](int level, int bx, int by, int h) {
    const Level& l = levels_[level];
    if (bx >= l.blocks_x || by >= l.blocks_y || !l.free[static_cast<size_t>(by) * l.blocks_x + bx]) return;
    ++last_block_scores_;
    open.push({BlockScore(l, bx, by, &rx[h * n], &ry[h * n], n), level, bx, by, h});
  };
  const int top = static_cast<int>(levels_.size()) - 1;
  for (int h = 0; h < headings; ++h)
    for (int by = 0; by < levels_[top].blocks_y; ++by)
      for (int bx = 0; bx < levels_[top].blocks_x; ++bx) push(top, bx, by, h);
  std::vector<Node> kept;
  const size_t keep = static_cast<size_t>(std::max(1, o_.blocks_refined));
  while (!open.empty() && kept.size() < keep) {
    const Node node = open.top();
    open.pop();
    if (node.level == 0) {
      kept.push_back(node);
      continue;
    }
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) push(node.level - 1, 2 * node.bx + dx, 2 * node.by + dy, node.heading);
  }
  if (kept.empty()) return {};

  // Fine: cell by cell within each kept block, quarter heading steps around its heading, by the
  // score of each point's cell; the best pose of each block is then scored by the likelihood
  // field itself (interpolated), which is what the candidates report.
  std::vector<PoseCandidate> fine;
  const int cells = levels_.front().cells, step = std::max(1, cells / 3);
  std::vector<float> qx(n), qy(n);
  for (const Node& k : kept) {
    const Point2 centre = origin_ + resolution_ * Point2((k.bx + 0.5) * cells, (k.by + 0.5) * cells);
    Pose2 best_pose;
    float best = -1.0f;
    for (int q = -2; q <= 2; ++q) {
      const double theta = NormalizeAngle(k.heading * 2.0 * M_PI / headings + q * 0.25 * 2.0 * M_PI / headings);
      const double c = std::cos(theta), s = std::sin(theta);
      for (size_t j = 0; j < n; ++j) {
        qx[j] = static_cast<float>((c * points[j].x() - s * points[j].y()) * inv);
        qy[j] = static_cast<float>((s * points[j].x() + c * points[j].y()) * inv);
      }
      for (int dy = -cells / 2; dy <= cells / 2; dy += step) {
        for (int dx = -cells / 2; dx <= cells / 2; dx += step) {
          const Pose2 pose{centre.x() + dx * resolution_, centre.y() + dy * resolution_, theta};
          const float px = static_cast<float>((pose.x - origin_.x()) * inv);
          const float py = static_cast<float>((pose.y - origin_.y()) * inv);
          float sum = 0.0f;
          for (size_t j = 0; j < n; ++j) {
            const int x = static_cast<int>(std::floor(px + qx[j])), y = static_cast<int>(std::floor(py + qy[j]));
            if (x >= 0 && y >= 0 && x < width_ && y < height_) sum += score_[static_cast<size_t>(y) * width_ + x];
          }
          if (sum > best) best = sum, best_pose = pose;
        }
      }
    }
    fine.push_back({best_pose, field_.Agreement(best_pose, points)});
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

}  // namespace navd::localization
