#include "services/planning/convex_cell_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_map>

#include "services/common/error.h"

namespace navd::planning {
namespace {

// A rectangle of the intersection grid's index space: lines [x0, x1) x [y0, y1).
struct IndexRect {
  int x0, x1, y0, y1;
};

// Positions (raster boundary indices) where some row or column changes between free and blocked,
// plus both ends: the extended boundary lines of the contracted map.
std::vector<int> BoundaryLines(const std::vector<uint8_t>& free, int width, int height, bool along_x) {
  const int n = along_x ? width : height, m = along_x ? height : width;
  std::vector<uint8_t> line(n + 1, 0);
  line[0] = line[n] = 1;
  for (int j = 0; j < m; ++j) {
    for (int i = 1; i < n; ++i) {
      const size_t here = along_x ? static_cast<size_t>(j) * width + i : static_cast<size_t>(i) * width + j;
      const size_t before = along_x ? here - 1 : here - width;
      if (free[here] != free[before]) line[i] = 1;
    }
  }
  std::vector<int> lines;
  for (int i = 0; i <= n; ++i)
    if (line[i]) lines.push_back(i);
  return lines;
}

// Joins the free rectangles of an nx x ny intersection grid: runs along the first axis, then runs
// of equal runs along the second. `rows_first` picks the first axis.
std::vector<IndexRect> JoinCells(const std::vector<uint8_t>& rect_free, int nx, int ny, bool rows_first) {
  const int outer = rows_first ? ny : nx, inner = rows_first ? nx : ny;
  auto is_free = [&](int o, int i) { return rows_first ? rect_free[o * nx + i] : rect_free[i * nx + o]; };
  std::vector<IndexRect> cells;
  std::unordered_map<int64_t, size_t> open, next_open;  // run [i0, i1) -> cell ending at the previous row
  for (int o = 0; o < outer; ++o) {
    next_open.clear();
    for (int i = 0; i < inner;) {
      if (!is_free(o, i)) {
        ++i;
        continue;
      }
      int end = i;
      while (end < inner && is_free(o, end)) ++end;
      const int64_t key = static_cast<int64_t>(i) * (inner + 1) + end;
      size_t id;
      if (auto it = open.find(key); it != open.end()) {
        id = it->second;  // the same run one row on: the union is still a rectangle
        (rows_first ? cells[id].y1 : cells[id].x1) = o + 1;
      } else {
        id = cells.size();
        cells.push_back(rows_first ? IndexRect{i, end, o, o + 1} : IndexRect{o, o + 1, i, end});
      }
      next_open[key] = id;
      i = end;
    }
    open.swap(next_open);
  }
  return cells;
}

// Cells with no obstacle (the costmap's policy for unknown space included) within k cells in x
// and in y: two sliding-window passes over prefix counts.
std::vector<uint8_t> SquareErode(const Costmap& costmap, int k) {
  const int w = costmap.width(), h = costmap.height();
  const double half_cell = 0.5 * costmap.grid().resolution();
  std::vector<uint8_t> near_x(static_cast<size_t>(w) * h), free(near_x.size());
  std::vector<int> prefix(std::max(w, h) + 1);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x)
      prefix[x + 1] = prefix[x] + (costmap.distance(static_cast<size_t>(y) * w + x) < half_cell);
    for (int x = 0; x < w; ++x)
      near_x[static_cast<size_t>(y) * w + x] = prefix[std::min(w, x + k + 1)] - prefix[std::max(0, x - k)] > 0;
  }
  for (int x = 0; x < w; ++x) {
    for (int y = 0; y < h; ++y) prefix[y + 1] = prefix[y] + near_x[static_cast<size_t>(y) * w + x];
    for (int y = 0; y < h; ++y) {
      const size_t i = static_cast<size_t>(y) * w + x;
      free[i] = prefix[std::min(h, y + k + 1)] - prefix[std::max(0, y - k)] == 0 && !costmap.lethal_data()[i];
    }
  }
  return free;
}

}  // namespace

ConvexCellMap::ConvexCellMap(const Costmap& costmap, double margin)
    : margin_(margin),
      width_(costmap.width()),
      height_(costmap.height()),
      resolution_(costmap.grid().resolution()),
      origin_(costmap.grid().origin()),
      label_(static_cast<size_t>(width_) * height_, -1) {
  if (!std::isfinite(margin) || margin < 0.0)
    throw Error(ErrorCode::kInvalidArgument, "margin must be a finite number of metres >= 0");
  // Step 1: the contracted map. Obstacles grow by a square of half-width inflation + margin (the
  // Chebyshev metric), not a disc: a wall's contraction then stays a straight wall with sharp
  // corners, as the seed's offset lines give, instead of a staircase of tiny cells. The square
  // holds the disc, so contracted-free cells are never lethal.
  const int k = static_cast<int>(std::ceil((costmap.options().inflation_radius + margin) / resolution_ - 1e-9));
  std::vector<uint8_t> free = SquareErode(costmap, k);
  // Step 2: the intersection grid of the extended boundary lines.
  const std::vector<int> xs = BoundaryLines(free, width_, height_, true);
  const std::vector<int> ys = BoundaryLines(free, width_, height_, false);
  const int nx = static_cast<int>(xs.size()) - 1, ny = static_cast<int>(ys.size()) - 1;
  // Step 3: which rectangles lie inside the contracted map (each is wholly free or blocked).
  std::vector<uint8_t> rect_free(static_cast<size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) rect_free[j * nx + i] = free[static_cast<size_t>(ys[j]) * width_ + xs[i]];
  // Step 4: join.
  std::vector<IndexRect> joined = JoinCells(rect_free, nx, ny, true);
  std::vector<IndexRect> by_columns = JoinCells(rect_free, nx, ny, false);
  if (by_columns.size() < joined.size()) joined.swap(by_columns);

  cells_.reserve(joined.size());
  for (size_t id = 0; id < joined.size(); ++id) {
    const IndexRect& r = joined[id];
    const int x0 = xs[r.x0], x1 = xs[r.x1], y0 = ys[r.y0], y1 = ys[r.y1];
    ConvexCell cell;
    cell.min = origin_ + resolution_ * Point2(x0, y0);
    cell.max = origin_ + resolution_ * Point2(x1, y1);
    cells_.push_back(cell);
    for (int y = y0; y < y1; ++y)
      std::fill(label_.begin() + static_cast<size_t>(y) * width_ + x0,
                label_.begin() + static_cast<size_t>(y) * width_ + x1, static_cast<int32_t>(id));
  }
  // Doorways: along each cell's right and top sides (a left or bottom side is another cell's right
  // or top), runs of one neighbour give one shared segment.
  for (size_t id = 0; id < cells_.size(); ++id) {
    const IndexRect& r = joined[id];
    for (const bool right : {true, false}) {
      const int fixed = right ? xs[r.x1] : ys[r.y1];
      if (fixed >= (right ? width_ : height_)) continue;
      const int from = right ? ys[r.y0] : xs[r.x0], to = right ? ys[r.y1] : xs[r.x1];
      for (int k = from; k < to;) {
        const int32_t n =
            right ? label_[static_cast<size_t>(k) * width_ + fixed] : label_[static_cast<size_t>(fixed) * width_ + k];
        int end = k + 1;
        while (end < to && (right ? label_[static_cast<size_t>(end) * width_ + fixed]
                                  : label_[static_cast<size_t>(fixed) * width_ + end]) == n)
          ++end;
        if (n >= 0) {
          Doorway d;
          d.cells[0] = static_cast<int32_t>(id);
          d.cells[1] = n;
          d.a = origin_ + resolution_ * (right ? Point2(fixed, k) : Point2(k, fixed));
          d.b = origin_ + resolution_ * (right ? Point2(fixed, end) : Point2(end, fixed));
          const int32_t door = static_cast<int32_t>(doorways_.size());
          doorways_.push_back(d);
          cells_[id].doorways.push_back(door);
          cells_[n].doorways.push_back(door);
        }
        k = end;
      }
    }
  }
}

Point2 ConvexCellMap::DoorwayPoint(int32_t door, double t) const {
  const Doorway& d = doorways_[door];
  const double len = Distance(d.a, d.b);
  const double keep = std::min(0.5 * resolution_, 0.5 * len);
  return d.a + (d.b - d.a) * ((keep + std::clamp(t, 0.0, 1.0) * (len - 2.0 * keep)) / len);
}

std::pair<Point2, Point2> ConvexCellMap::Crossing(int32_t door, int32_t from, const Point2& q) const {
  const Doorway& d = doorways_[door];
  const Point2 side = (d.b - d.a).normalized();
  Point2 normal(-side.y(), side.x());
  if (normal.dot(cells_[from].centre() - q) < 0.0) normal = -normal;  // towards `from`
  const double step = 0.25 * resolution_;
  return {q + step * normal, q - step * normal};
}

int32_t ConvexCellMap::CellAt(const Point2& p) const {
  const double fx = std::floor((p.x() - origin_.x()) / resolution_),
               fy = std::floor((p.y() - origin_.y()) / resolution_);
  if (!(fx >= 0 && fy >= 0 && fx < width_ && fy < height_)) return -1;
  return label_[static_cast<size_t>(fy) * width_ + static_cast<size_t>(fx)];
}

CellEntry ConvexCellMap::Enter(const Costmap& costmap, const Point2& p, double reach, const std::string& what) const {
  if (const int32_t cell = CellAt(p); cell >= 0) return {cell, p};
  // The nearest points of the cells around p, nearest first, until one is reachable in a straight line.
  const int r = static_cast<int>(std::ceil(reach / resolution_));
  const int cx = static_cast<int>(std::floor((p.x() - origin_.x()) / resolution_));
  const int cy = static_cast<int>(std::floor((p.y() - origin_.y()) / resolution_));
  std::vector<std::pair<double, int32_t>> candidates;
  for (int y = std::max(0, cy - r); y <= std::min(height_ - 1, cy + r); ++y) {
    for (int x = std::max(0, cx - r); x <= std::min(width_ - 1, cx + r); ++x) {
      const int32_t cell = label_[static_cast<size_t>(y) * width_ + x];
      if (cell < 0) continue;
      const ConvexCell& c = cells_[cell];
      const Point2 q = p.cwiseMax(c.min).cwiseMin(c.max);
      candidates.emplace_back(Distance(p, q), cell);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  for (const auto& [d, cell] : candidates) {
    if (d > reach) break;
    const ConvexCell& c = cells_[cell];
    // Just inside the cell, so later segments from it stay inside.
    const double inset = std::min(0.25 * resolution_, 0.25 * (c.max - c.min).minCoeff());
    const Point2 q = p.cwiseMax(c.min + Point2(inset, inset)).cwiseMin(c.max - Point2(inset, inset));
    if (costmap.SegmentFree(p, q)) return {cell, q};
  }
  char buf[200];
  std::snprintf(buf, sizeof buf, "%s (%.2f, %.2f) is not within %.2f m of the convex navigation grid (margin %.2f m)",
                what.c_str(), p.x(), p.y(), reach, margin_);
  throw Error(ErrorCode::kNotFound, buf);
}

std::shared_ptr<const ConvexCellMap> ConvexCellMapCache::Get(const Costmap& costmap, double margin) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto& grid = costmap.grid_ptr();
  const bool same_map = !grid_.owner_before(grid) && !grid.owner_before(grid_) && !grid_.expired();
  const CostmapOptions& o = costmap.options();
  if (!map_ || !same_map || map_->margin() != margin || o.inflation_radius != costmap_options_.inflation_radius ||
      o.unknown_is_lethal != costmap_options_.unknown_is_lethal) {
    map_ = std::make_shared<const ConvexCellMap>(costmap, margin);
    grid_ = grid;
    costmap_options_ = o;
  }
  return map_;
}

}  // namespace navd::planning
