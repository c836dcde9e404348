#include "services/planning/elastic_band.h"

#include <algorithm>
#include <cmath>

namespace navd::planning {
namespace {

std::vector<Point2> Resample(const std::vector<Point2>& path, double spacing) {
  std::vector<Point2> out{path.front()};
  for (size_t i = 1; i < path.size(); ++i) {
    const Point2 &a = path[i - 1], &b = path[i];
    const int pieces = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing)));
    for (int k = 1; k <= pieces; ++k) out.emplace_back(a + (b - a) * (static_cast<double>(k) / pieces));
  }
  return out;
}

// Distance to the nearest obstacle at p (metres, from the costmap's cell-centre field) and its
// gradient by central differences over neighbouring cells.
double Clearance(const Costmap& costmap, const Point2& p, Point2* gradient) {
  const OccupancyGrid& g = costmap.grid();
  const CellIndex c = g.CellOf(p);
  auto at = [&](int x, int y) {
    const CellIndex q{std::clamp(x, 0, g.width() - 1), std::clamp(y, 0, g.height() - 1)};
    const double d = costmap.distance(g.Flat(q));
    return std::isfinite(d) ? d : 1e3;
  };
  *gradient = Point2(at(c.x + 1, c.y) - at(c.x - 1, c.y), at(c.x, c.y + 1) - at(c.x, c.y - 1)) / (2.0 * g.resolution());
  return at(c.x, c.y);
}

}  // namespace

std::vector<Point2> ElasticBand(const Costmap& costmap, const std::vector<Point2>& path, const ElasticBandOptions& o) {
  if (path.size() < 2) return path;
  std::vector<Point2> band = Resample(path, o.spacing);
  const size_t n = band.size();
  for (int it = 0; it < o.iterations; ++it) {
    for (size_t i = 1; i + 1 < n; ++i) {
      Point2 force = o.contraction * (0.5 * (band[i - 1] + band[i + 1]) - band[i]);
      if (i >= 2 && i + 2 < n) {
        force -= o.curvature * (band[i - 2] - 4.0 * band[i - 1] + 6.0 * band[i] - 4.0 * band[i + 1] + band[i + 2]);
      }
      Point2 gradient;
      const double d = Clearance(costmap, band[i], &gradient);
      if (d < o.influence && gradient.norm() > 0.0)
        force += o.obstacle * (o.influence - d) * gradient.normalized() * o.spacing;
      const Point2 moved = band[i] + force;
      if (costmap.SegmentFree(band[i - 1], moved) && costmap.SegmentFree(moved, band[i + 1])) band[i] = moved;
    }
  }
  return band;
}

double MaxTurn(const std::vector<Point2>& path) {
  double worst = 0.0;
  for (size_t i = 1; i + 1 < path.size(); ++i) {
    const Point2 a = path[i] - path[i - 1], b = path[i + 1] - path[i];
    if (a.norm() == 0.0 || b.norm() == 0.0) continue;
    worst = std::max(worst, std::abs(std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b))));
  }
  return worst;
}

}  // namespace navd::planning
