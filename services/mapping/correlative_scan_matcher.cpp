#include "services/mapping/correlative_scan_matcher.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "services/common/error.h"
#include "services/mapping/recycled_cells.h"

namespace navd::mapping {
namespace {

// The fine search's sums: a scan's bilinear lookups at 7 x 7 offsets of a sixth of a cell, each
// point adding its lookups at every offset (in the points' order, as adding the points offset by
// offset would). Offsets of at most half a cell either way keep a point's lookups within the 3 x 3
// cells from its lowest one, and the bilinear weights split by axis: its 49 lookups read 9 cells
// and take 7 weights per axis.
class SubCellSums {
 public:
  static constexpr int kSub = 3;  // sixths of a cell either way
  static constexpr int kSide = 2 * kSub + 1;

  SubCellSums() {
    for (int i = 0; i < kSide; ++i) offsets_[i] = (i - kSub) / 6.0;
  }
  void Clear() { sums_.fill(0.0); }
  // Adds the lookups of a point at (gx, gy), in cell units from cell (0, 0)'s centre.
  void Add(const CorrelationGrid& grid, double gx, double gy) {
    const int low_x = static_cast<int>(std::floor(gx + offsets_[0]));
    const int low_y = static_cast<int>(std::floor(gy + offsets_[0]));
    std::array<int, kSide> cell_x{}, cell_y{};
    std::array<double, kSide> weight_x{}, weight_y{};
    Split(gx, low_x, cell_x, weight_x);
    Split(gy, low_y, cell_y, weight_y);
    std::array<std::array<float, 3>, 3> patch{};  // [row][column] from the lowest cell
    for (int r = 0; r < 3; ++r)
      for (int q = 0; q < 3; ++q) patch[r][q] = grid.AtCell(low_x + q, low_y + r);
    std::array<std::array<double, kSide>, 3> along{};  // each row interpolated at each x offset
    for (int r = 0; r < 3; ++r)
      for (int i = 0; i < kSide; ++i)
        along[r][i] = (1 - weight_x[i]) * patch[r][cell_x[i]] + weight_x[i] * patch[r][cell_x[i] + 1];
    for (int j = 0; j < kSide; ++j) {
      const std::array<double, kSide>& below = along[cell_y[j]];
      const std::array<double, kSide>& above = along[cell_y[j] + 1];
      for (int i = 0; i < kSide; ++i) sums_[j * kSide + i] += (1 - weight_y[j]) * below[i] + weight_y[j] * above[i];
    }
  }
  // The sum at an offset of (i, j) sixths of a cell, each in -kSub..kSub.
  double At(int i, int j) const { return sums_[(j + kSub) * kSide + (i + kSub)]; }

 private:
  // Where each offset's lookup along one axis falls: the lower of its two cells (0 or 1 from the
  // lowest) and the upper one's weight.
  void Split(double g, int lowest, std::array<int, kSide>& cell, std::array<double, kSide>& weight) const {
    for (int i = 0; i < kSide; ++i) {
      const double f = g + offsets_[i];
      const int c = static_cast<int>(std::floor(f));
      cell[i] = std::clamp(c - lowest, 0, 1);
      weight[i] = f - c;
    }
  }

  std::array<double, kSide> offsets_{};  // cells
  std::array<double, kSide * kSide> sums_{};
};

}  // namespace

CorrelationGrid::CorrelationGrid(const std::vector<Point2>& reference, double resolution, double sigma)
    : resolution_(resolution) {
  if (reference.empty()) return;
  const double reach = 3.0 * sigma;
  Point2 lo = reference.front(), hi = reference.front();
  for (const Point2& p : reference) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  // A margin of the smear plus the largest window anyone searches (loop closures: a few metres).
  const double margin = reach + 2.0 * resolution;
  origin_ = Point2(std::floor((lo.x() - margin) / resolution) * resolution,
                   std::floor((lo.y() - margin) / resolution) * resolution);
  width_ = static_cast<int>(std::ceil((hi.x() + margin - origin_.x()) / resolution)) + 1;
  height_ = static_cast<int>(std::ceil((hi.y() + margin - origin_.y()) / resolution)) + 1;
  if (static_cast<long long>(width_) * height_ > 64'000'000LL)
    throw Error(ErrorCode::kInvalidArgument, "scan matching: reference points span too large an area");
  cells_ = RecycledCells::Take(static_cast<size_t>(width_) * height_);
  const int r = static_cast<int>(std::ceil(reach / resolution));
  const double inv = 1.0 / (2.0 * sigma * sigma);
  const double reach2 = reach * reach;
  // exp(-q) tabulated over the smear's reach (q <= 4.5 inside 3 sigma): the grid is rebuilt for
  // every scan, and exp would be most of its cost.
  constexpr int kTable = 512;
  constexpr double kMaxQ = 4.5;
  static const std::vector<float> table = [] {
    std::vector<float> t(kTable + 2);
    for (int i = 0; i < kTable + 2; ++i) t[i] = static_cast<float>(std::exp(-kMaxQ * i / kTable));
    return t;
  }();
  auto smear = [&](double d2) {  // exp(-d2 inv) for d2 (m²) within the reach
    const double q = std::min(d2 * inv, kMaxQ) * (kTable / kMaxQ);
    const int i = static_cast<int>(q);
    return table[i] + static_cast<float>(q - i) * (table[i + 1] - table[i]);
  };
  // A point's smear is a column factor times a row factor, exp(-dx² inv) exp(-dy² inv), cut at
  // `reach`: each cell within it costs a product and a max.
  std::vector<double> dx2(static_cast<size_t>(2 * r + 1));
  std::vector<float> column_factor(dx2.size());
  for (const Point2& p : reference) {
    const int cx = CellX(p.x()), cy = CellY(p.y());
    for (int i = 0; i <= 2 * r; ++i) {
      const double dx = origin_.x() + (cx - r + i + 0.5) * resolution - p.x();
      dx2[i] = dx * dx;
      column_factor[i] = smear(dx2[i]);
    }
    for (int y = cy - r; y <= cy + r; ++y) {
      const double dy = origin_.y() + (y + 0.5) * resolution - p.y();
      const double dx2_limit = reach2 - dy * dy;
      if (dx2_limit <= 0.0) continue;
      const float row_factor = smear(dy * dy);
      float* row = &cells_[static_cast<size_t>(y) * width_ + (cx - r)];
      for (int i = 0; i <= 2 * r; ++i) {
        const float v = dx2[i] < dx2_limit ? column_factor[i] * row_factor : 0.0f;
        row[i] = std::max(row[i], v);
      }
    }
  }
}

CorrelationGrid::~CorrelationGrid() { RecycledCells::Give(std::move(cells_)); }

std::vector<Point2> ThinPoints(const std::vector<Point2>& points, double spacing) {
  std::vector<Point2> out;
  for (const Point2& p : points)
    if (out.empty() || Distance(out.back(), p) >= spacing) out.push_back(p);
  return out;
}

std::vector<Point2> ThinPointsTo(const std::vector<Point2>& points, size_t min_points, double max_spacing) {
  if (points.size() <= min_points) return points;
  std::vector<Point2> widest = ThinPoints(points, max_spacing);
  if (widest.size() >= min_points) return widest;
  // The count falls as the spacing grows: bisect to a millimetre.
  double lo = 0.0, hi = max_spacing;
  std::vector<Point2> kept = points;
  while (hi - lo > 1e-3) {
    const double mid = 0.5 * (lo + hi);
    std::vector<Point2> thinned = ThinPoints(points, mid);
    if (thinned.size() >= min_points) {
      lo = mid;
      kept = std::move(thinned);
    } else {
      hi = mid;
    }
  }
  return kept;
}

ScanMatch MatchScan(const CorrelationGrid& grid, const std::vector<Point2>& points, const Pose2& prior,
                    const ScanMatchOptions& o) {
  ScanMatch best{prior, 0.0};
  if (grid.empty() || points.empty()) return best;
  const double res = grid.resolution();
  const int n_xy = static_cast<int>(std::ceil(o.window_xy / res));
  const int n_theta = static_cast<int>(std::ceil(o.window_theta / o.angle_step));
  const double inv_n = 1.0 / static_cast<double>(points.size());
  const double kxy = o.prior_sigma_xy > 0.0 ? 0.5 / (o.prior_sigma_xy * o.prior_sigma_xy) : 0.0;
  const double kt = o.prior_sigma_theta > 0.0 ? 0.5 / (o.prior_sigma_theta * o.prior_sigma_theta) : 0.0;
  auto prior_weight = [&](double dx, double dy, double dtheta) {
    return kxy == 0.0 && kt == 0.0 ? 1.0 : std::exp(-kxy * (dx * dx + dy * dy) - kt * dtheta * dtheta);
  };
  double best_ranked = 0.0;

  // Coarse: every angle, whole-cell offsets (integer lookups of the rotated points' cells).
  struct Candidate {
    double score;
    int dx, dy;
    double theta;
  };
  std::vector<Candidate> top;  // the best few, best first
  std::vector<int> cx(points.size()), cy(points.size());
  std::vector<char> inside(points.size());  // every cell of the point's window lies on the grid
  const int side = 2 * n_xy + 1;
  std::vector<double> row_sums(static_cast<size_t>(side));
  std::vector<float> coarse;  // every coarse score, for the ambiguity check
  if (o.distinct_xy > 0.0) coarse.resize(static_cast<size_t>(2 * n_theta + 1) * side * side);
  for (int a = -n_theta; a <= n_theta; ++a) {
    const double theta = prior.theta + a * o.angle_step;
    const double c = std::cos(theta), s = std::sin(theta);
    for (size_t i = 0; i < points.size(); ++i) {
      const Point2& p = points[i];
      cx[i] = grid.CellX(prior.x + c * p.x() - s * p.y());
      cy[i] = grid.CellY(prior.y + s * p.x() + c * p.y());
      inside[i] = cx[i] - n_xy >= 0 && cx[i] + n_xy < grid.width() && cy[i] - n_xy >= 0 && cy[i] + n_xy < grid.height();
    }
    for (int dy = -n_xy; dy <= n_xy; ++dy) {
      // Each point adds its row of the window to every offset's sum at once: contiguous cells, in
      // the points' order, so each sum is the same as adding the points offset by offset.
      std::fill(row_sums.begin(), row_sums.end(), 0.0);
      for (size_t i = 0; i < points.size(); ++i) {
        if (inside[i]) {
          const float* cells = grid.Row(cy[i] + dy) + (cx[i] - n_xy);
          for (int k = 0; k < side; ++k) row_sums[k] += cells[k];
        } else {
          for (int k = 0; k < side; ++k) row_sums[k] += grid.AtCell(cx[i] - n_xy + k, cy[i] + dy);
        }
      }
      for (int dx = -n_xy; dx <= n_xy; ++dx) {
        const double score = row_sums[dx + n_xy] * inv_n;
        if (!coarse.empty())
          coarse[(static_cast<size_t>(a + n_theta) * side + (dy + n_xy)) * side + (dx + n_xy)] =
              static_cast<float>(score);
        const double ranked = score * prior_weight(dx * res, dy * res, a * o.angle_step);
        if (static_cast<int>(top.size()) < o.refine_candidates || ranked > top.back().score) {
          top.push_back({ranked, dx, dy, theta});
          std::sort(top.begin(), top.end(), [](const Candidate& l, const Candidate& r) { return l.score > r.score; });
          if (static_cast<int>(top.size()) > o.refine_candidates) top.pop_back();
        }
      }
    }
  }

  double coarse_best = 0.0, coarse_elsewhere = 0.0, coarse_spread = 0.0;
  if (!coarse.empty() && !top.empty()) {
    const int best_a = static_cast<int>(std::lround((top.front().theta - prior.theta) / o.angle_step)) + n_theta;
    coarse_best =
        coarse[(static_cast<size_t>(best_a) * side + (top.front().dy + n_xy)) * side + (top.front().dx + n_xy)];
    const double min_cells = o.distinct_xy / res;
    const double min_steps = o.distinct_theta > 0.0 ? o.distinct_theta / o.angle_step : 1e18;
    for (int a = 0; a < 2 * n_theta + 1; ++a) {
      const bool turned = std::abs(a - best_a) >= min_steps;
      for (int dy = -n_xy; dy <= n_xy; ++dy) {
        for (int dx = -n_xy; dx <= n_xy; ++dx) {
          const double score = coarse[(static_cast<size_t>(a) * side + (dy + n_xy)) * side + (dx + n_xy)];
          const double cells = std::hypot(dx - top.front().dx, dy - top.front().dy);
          if (cells >= min_cells || turned) coarse_elsewhere = std::max(coarse_elsewhere, score);
          if (score >= 0.95 * coarse_best) coarse_spread = std::max(coarse_spread, cells * res);
        }
      }
    }
  }

  // Fine: sixths of a cell and quarter angle steps, half a coarse step either way of each coarse
  // winner, bilinear lookups.
  constexpr int kSub = SubCellSums::kSub;
  SubCellSums sums;
  for (const Candidate& cand : top) {
    const double x0 = prior.x + cand.dx * res, y0 = prior.y + cand.dy * res;
    for (int a = -2; a <= 2; ++a) {
      const double theta = cand.theta + a * o.angle_step / 4.0;
      const double c = std::cos(theta), s = std::sin(theta);
      sums.Clear();
      for (const Point2& p : points)
        sums.Add(grid, grid.CellUnitsX(x0 + c * p.x() - s * p.y()), grid.CellUnitsY(y0 + s * p.x() + c * p.y()));
      for (int j = -kSub; j <= kSub; ++j) {
        for (int i = -kSub; i <= kSub; ++i) {
          const double x = x0 + i * res / 6.0, y = y0 + j * res / 6.0;
          const double score = sums.At(i, j) * inv_n;
          const double ranked = score * prior_weight(x - prior.x, y - prior.y, NormalizeAngle(theta - prior.theta));
          if (ranked > best_ranked) {
            best_ranked = ranked;
            best = {{x, y, NormalizeAngle(theta)}, score};
          }
        }
      }
    }
  }
  best.coarse_best = coarse_best;
  best.coarse_elsewhere = coarse_elsewhere;
  best.coarse_spread = coarse_spread;
  return best;
}

}  // namespace navd::mapping
