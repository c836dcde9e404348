#include "services/common/polygon.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "services/common/grid_traversal.h"

namespace navd {
namespace {

double Cross(const Point2& a, const Point2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Orientation of c relative to the line a->b: +1 left, -1 right, 0 collinear.
int Orientation(const Point2& a, const Point2& b, const Point2& c) {
  const double v = Cross(b - a, c - a);
  const double eps = 1e-12 * std::max(1.0, (b - a).squaredNorm() + (c - a).squaredNorm());
  return v > eps ? 1 : (v < -eps ? -1 : 0);
}

bool OnSegment(const Point2& a, const Point2& b, const Point2& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) && std::min(a.y(), b.y()) <= p.y() &&
         p.y() <= std::max(a.y(), b.y());
}

bool SegmentsIntersect(const Point2& p1, const Point2& p2, const Point2& q1, const Point2& q2) {
  const int o1 = Orientation(p1, p2, q1), o2 = Orientation(p1, p2, q2);
  const int o3 = Orientation(q1, q2, p1), o4 = Orientation(q1, q2, p2);
  if (o1 != o2 && o3 != o4 && o1 != 0 && o2 != 0 && o3 != 0 && o4 != 0) return true;
  return (o1 == 0 && OnSegment(p1, p2, q1)) || (o2 == 0 && OnSegment(p1, p2, q2)) ||
         (o3 == 0 && OnSegment(q1, q2, p1)) || (o4 == 0 && OnSegment(q1, q2, p2)) || (o1 != o2 && o3 != o4);
}

void FillEdges(OccupancyGrid& grid, const Polygon& polygon, int8_t value) {
  for (size_t i = 0; i < polygon.size(); ++i) {
    TraverseSegment(grid, polygon[i], polygon[(i + 1) % polygon.size()], [&](const CellIndex& c, double) {
      if (grid.Contains(c)) grid.set(c, value);
      return true;
    });
  }
}

}  // namespace

std::optional<std::string> PolygonDefect(const Polygon& polygon) {
  const size_t n = polygon.size();
  if (n < 3) return "needs at least 3 vertices";
  for (const auto& p : polygon) {
    if (!p.allFinite()) return "has a non-finite vertex";
  }
  double area2 = 0.0;
  for (size_t i = 0; i < n; ++i) area2 += Cross(polygon[i], polygon[(i + 1) % n]);
  if (std::abs(area2) < 1e-12) return "has zero area";
  for (size_t i = 0; i < n; ++i) {
    const Point2 &a = polygon[i], &b = polygon[(i + 1) % n];
    if ((a - b).norm() == 0.0) return "repeats vertex " + std::to_string(i);
    for (size_t j = i + 1; j < n; ++j) {
      // Neighbouring edges share a vertex; they only fail if they fold back onto each other.
      const bool adjacent = j == i + 1 || (i == 0 && j == n - 1);
      const Point2 &c = polygon[j], &d = polygon[(j + 1) % n];
      if (adjacent) {
        const Point2 shared = j == i + 1 ? b : a;
        const Point2 u = (j == i + 1 ? a : b) - shared, v = (j == i + 1 ? d : c) - shared;
        if (std::abs(Cross(u, v)) < 1e-12 * u.norm() * v.norm() && u.dot(v) > 0) {
          return "folds back on itself at vertex " + std::to_string(j == i + 1 ? j : 0);
        }
        continue;
      }
      if (SegmentsIntersect(a, b, c, d)) {
        return "intersects itself (edges " + std::to_string(i) + " and " + std::to_string(j) + " cross)";
      }
    }
  }
  return std::nullopt;
}

bool PolygonContains(const Polygon& polygon, const Point2& p) {
  bool inside = false;
  for (size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Point2 &a = polygon[i], &b = polygon[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

void FillPolygon(OccupancyGrid& grid, const Polygon& polygon, int8_t value) {
  Point2 lo = polygon[0], hi = polygon[0];
  for (const auto& p : polygon) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const CellIndex a = grid.CellOf(lo), b = grid.CellOf(hi);
  for (int y = std::max(a.y, 0); y <= std::min(b.y, grid.height() - 1); ++y) {
    for (int x = std::max(a.x, 0); x <= std::min(b.x, grid.width() - 1); ++x) {
      if (PolygonContains(polygon, grid.CellCenter({x, y}))) grid.set({x, y}, value);
    }
  }
  FillEdges(grid, polygon, value);
}

void FillOutsidePolygon(OccupancyGrid& grid, const Polygon& polygon, int8_t value) {
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      if (!PolygonContains(polygon, grid.CellCenter({x, y}))) grid.set({x, y}, value);
    }
  }
  FillEdges(grid, polygon, value);
}

double DistanceToSegment(const Point2& p, const Point2& a, const Point2& b) {
  const Point2 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm();
}

double DistanceToBoundary(const Polygon& polygon, const Point2& p) {
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < polygon.size(); ++i)
    best = std::min(best, DistanceToSegment(p, polygon[i], polygon[(i + 1) % polygon.size()]));
  return best;
}

}  // namespace navd
