#include "services/common/distance_field.h"

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
  std::vector<double> squared(distance_.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int8_t c = grid.at({x, y});
      const bool obstacle = c >= OccupancyGrid::kOccupiedThreshold || (unknown_is_obstacle && c < 0);
      squared[static_cast<size_t>(y) * w + x] = obstacle ? 0.0 : kFar;
    }
  for (int x = 0; x < w; ++x) {  // columns
    for (int y = 0; y < h; ++y) f[y] = squared[static_cast<size_t>(y) * w + x];
    Transform1d(f, h, d, v, z);
    for (int y = 0; y < h; ++y) squared[static_cast<size_t>(y) * w + x] = d[y];
  }
  for (int y = 0; y < h; ++y) {  // rows
    for (int x = 0; x < w; ++x) f[x] = squared[static_cast<size_t>(y) * w + x];
    Transform1d(f, w, d, v, z);
    for (int x = 0; x < w; ++x) {
      distance_[static_cast<size_t>(y) * w + x] =
          d[x] >= kFar / 2 ? std::numeric_limits<double>::infinity() : std::sqrt(d[x]) * grid.resolution();
    }
  }
}

}  // namespace navd
