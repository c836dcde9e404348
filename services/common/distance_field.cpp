#include "services/common/distance_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace navd {
namespace {

constexpr double kFar = 1e20;  // "no obstacle": finite so the parabola arithmetic stays defined

// 1-D squared distance transform of f (lower envelope of parabolas), into d.
void Transform1d(const std::vector<double>& f, int n, std::vector<double>& d, std::vector<int>& v,
                 std::vector<double>& z) {
  int k = 0;
  v[0] = 0;
  z[0] = -std::numeric_limits<double>::infinity();
  z[1] = std::numeric_limits<double>::infinity();
  for (int q = 1; q < n; ++q) {
    // Intersection of parabola q with the rightmost one kept; z[0] = -inf ends the loop.
    auto intersect = [&](int p) {
      return ((f[q] + static_cast<double>(q) * q) - (f[p] + static_cast<double>(p) * p)) / (2.0 * q - 2.0 * p);
    };
    double s = intersect(v[k]);
    while (s <= z[k]) s = intersect(v[--k]);
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = std::numeric_limits<double>::infinity();
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    const double dq = q - v[k];
    d[q] = dq * dq + f[v[k]];
  }
}

}  // namespace

DistanceField::DistanceField(const OccupancyGrid& grid, bool unknown_is_obstacle)
    : width_(grid.width()), distance_(grid.cells().size()) {
  const int w = grid.width(), h = grid.height();
  const int n = std::max(w, h);
  std::vector<double> f(n), d(n), z(n + 1);
  std::vector<int> v(n);
  // Along columns the input is binary (obstacle or not), so the 1-D transform is the squared
  // distance to the nearest obstacle cell in the column: two sweeps over whole rows (Meijster's
  // first phase), in memory order, instead of a parabola envelope per column.
  constexpr int kNone = std::numeric_limits<int>::max() / 2;
  std::vector<int> gap(distance_.size());
  for (int y = 0; y < h; ++y) {
    const int* below = y > 0 ? &gap[static_cast<size_t>(y - 1) * w] : nullptr;
    int* row = &gap[static_cast<size_t>(y) * w];
    for (int x = 0; x < w; ++x) {
      const int8_t c = grid.at({x, y});
      const bool obstacle = c >= OccupancyGrid::kOccupiedThreshold || (unknown_is_obstacle && c < 0);
      row[x] = obstacle ? 0 : below ? std::min(kNone, below[x] + 1) : kNone;
    }
  }
  for (int y = h - 2; y >= 0; --y) {
    const int* above = &gap[static_cast<size_t>(y + 1) * w];
    int* row = &gap[static_cast<size_t>(y) * w];
    for (int x = 0; x < w; ++x) row[x] = std::min(row[x], above[x] + 1);
  }
  for (int y = 0; y < h; ++y) {  // rows: the parabola envelope over the columns' squared distances
    const int* row = &gap[static_cast<size_t>(y) * w];
    for (int x = 0; x < w; ++x) f[x] = row[x] >= kNone ? kFar : static_cast<double>(row[x]) * row[x];
    Transform1d(f, w, d, v, z);
    for (int x = 0; x < w; ++x) {
      distance_[static_cast<size_t>(y) * w + x] =
          d[x] >= kFar / 2 ? std::numeric_limits<double>::infinity() : std::sqrt(d[x]) * grid.resolution();
    }
  }
}

}  // namespace navd
