#include "services/planning/voronoi_fast_marching_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "services/common/error.h"
#include "services/planning/quaternary_heap.h"

namespace navd::planning {
namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

std::vector<double> FastMarch(int w, int h, double res, const std::vector<double>& speed, const CellIndex& goal,
                              const StopRequested& stop) {
  const size_t n = static_cast<size_t>(w) * h;
  // The grid is padded by one frozen, unreachable cell on every side, so the inner loop needs no
  // bounds checks. Times are floats: the scheme's own error (first order) dwarfs float rounding,
  // and half the memory traffic is most of the speed on large maps.
  const int pw = w + 2;
  const size_t pn = static_cast<size_t>(pw) * (h + 2);
  constexpr float kFar = std::numeric_limits<float>::infinity();
  std::vector<float> t(pn, kFar);
  std::vector<float> step(pn, 0.0f);  // res / speed: the time to cross a cell; 0 = impassable
  std::vector<uint8_t> frozen(pn, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double v = speed[static_cast<size_t>(y) * w + x];
      const size_t p = static_cast<size_t>(y + 1) * pw + x + 1;
      if (v > 0.0) {
        step[p] = static_cast<float>(res / v);
        frozen[p] = 0;
      }
    }
  QuaternaryHeap<float> trial;  // 8-byte entries
  const int32_t g = (goal.y + 1) * pw + goal.x + 1;
  t[g] = 0.0f;
  trial.push(0.0f, g);
  uint64_t popped = 0;
  const int32_t offsets[4] = {-1, 1, -pw, pw};
  while (!trial.empty()) {
    const auto e = trial.pop();
    if (frozen[e.node] && e.node != g) continue;
    if (e.key > t[e.node]) continue;
    frozen[e.node] = 1;
    if ((++popped & 16383) == 1 && stop && stop()) {
      throw Error(ErrorCode::kDeadlineExceeded, "fast marching stopped: deadline exceeded or cancelled");
    }
    for (const int32_t off : offsets) {
      const int32_t nb = e.node + off;
      if (frozen[nb]) continue;
      // Upwind neighbours along x and y.
      const float a = std::min(t[nb - 1], t[nb + 1]);
      const float b = std::min(t[nb - pw], t[nb + pw]);
      const float f = step[nb];
      float value;
      if (std::abs(a - b) >= f || !(std::abs(a - b) < kFar)) {
        value = std::min(a, b) + f;
      } else {
        value = 0.5f * (a + b + std::sqrt(2.0f * f * f - (a - b) * (a - b)));
      }
      if (value < t[nb]) {
        t[nb] = value;
        trial.push(value, nb);
      }
    }
  }
  std::vector<double> out(n);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) out[static_cast<size_t>(y) * w + x] = t[static_cast<size_t>(y + 1) * pw + x + 1];
  return out;
}

CellPath VoronoiFastMarchingPlanner::Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                                          const PlannerOptions& options, const StopRequested& stop) const {
  const double saturation = options.at("saturation"), min_speed = options.at("min_speed");
  if (!(saturation > 0.0)) throw Error(ErrorCode::kInvalidArgument, "options: 'saturation' must be > 0");
  if (!(min_speed > 0.0 && min_speed <= 1.0)) {
    throw Error(ErrorCode::kInvalidArgument, "options: 'min_speed' must be in (0, 1]");
  }
  const OccupancyGrid& grid = costmap.grid();
  const int w = costmap.width(), h = costmap.height();
  const double res = grid.resolution();
  // EVT of the enlarged obstacles: the lethal set is every point within the inflation radius of
  // an obstacle, so the distance to it is the costmap's obstacle distance minus that radius.
  const uint8_t* lethal = costmap.lethal_data();
  const double inflation = costmap.options().inflation_radius;
  // Speed: the logarithm of the EVT, saturating at `saturation` metres of clearance.
  const double top = std::log1p(saturation);
  std::vector<double> speed(grid.cells().size());
  for (size_t i = 0; i < speed.size(); ++i) {
    if (lethal[i]) {
      speed[i] = 0.0;
    } else {
      const double d = std::min(std::max(0.0, costmap.distance(i) - inflation), saturation);
      speed[i] = std::max(min_speed, std::log1p(d) / top);
    }
  }
  const std::vector<double> t = FastMarch(w, h, res, speed, goal, stop);
  CellPath result;
  const int32_t s = start.y * w + start.x;
  if (!std::isfinite(t[s])) return result;

  // Gradient descent on T, in cell units, with T bilinearly interpolated between cell centres.
  double t_max = 0.0;
  for (double v : t)
    if (std::isfinite(v)) t_max = std::max(t_max, v);
  auto at = [&](int x, int y) {
    x = std::clamp(x, 0, w - 1);
    y = std::clamp(y, 0, h - 1);
    const double v = t[static_cast<size_t>(y) * w + x];
    return std::isfinite(v) ? v : 2.0 * t_max + 1.0;  // walls: uphill everywhere
  };
  auto interpolate = [&](double px, double py) {
    const int x0 = static_cast<int>(std::floor(px)), y0 = static_cast<int>(std::floor(py));
    const double fx = px - x0, fy = py - y0;
    return (1 - fx) * (1 - fy) * at(x0, y0) + fx * (1 - fy) * at(x0 + 1, y0) + (1 - fx) * fy * at(x0, y0 + 1) +
           fx * fy * at(x0 + 1, y0 + 1);
  };
  const double step = 0.5;  // cells
  double px = start.x, py = start.y;
  result.cells.push_back(start);
  result.points.push_back(grid.CellCenter(start));
  result.speed_limits.push_back(speed[s]);
  const size_t max_steps = 8 * static_cast<size_t>(w + h) + static_cast<size_t>(4.0 * t[s] / res / min_speed);
  for (size_t i = 0; i < max_steps; ++i) {
    if (std::hypot(px - goal.x, py - goal.y) <= 1.0) break;
    const double gx = interpolate(px + 0.5, py) - interpolate(px - 0.5, py);
    const double gy = interpolate(px, py + 0.5) - interpolate(px, py - 0.5);
    const double norm = std::hypot(gx, gy);
    double nx, ny;
    if (norm < 1e-12) {
      // Flat spot (rare, at exact symmetry): take the lowest neighbouring cell.
      const int cx = static_cast<int>(std::lround(px)), cy = static_cast<int>(std::lround(py));
      int bx = cx, by = cy;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (at(cx + dx, cy + dy) < at(bx, by)) bx = cx + dx, by = cy + dy;
      if (bx == cx && by == cy) return {};
      nx = bx;
      ny = by;
    } else {
      nx = px - step * gx / norm;
      ny = py - step * gy / norm;
    }
    const CellIndex c{static_cast<int>(std::lround(nx)), static_cast<int>(std::lround(ny))};
    if (!grid.Contains(c) || lethal[grid.Flat(c)]) return {};  // descended into a wall: no safe path
    px = nx;
    py = ny;
    const Point2 p = grid.origin() + Point2(px + 0.5, py + 0.5) * res;
    if (!costmap.SegmentFree(result.points.back(), p)) return {};
    result.points.push_back(p);
    result.cells.push_back(c);
    result.speed_limits.push_back(speed[grid.Flat(c)]);
  }
  if (std::hypot(px - goal.x, py - goal.y) > 1.0) return {};
  result.cells.push_back(goal);
  result.points.push_back(grid.CellCenter(goal));
  result.speed_limits.push_back(speed[goal.y * w + goal.x]);
  result.keep_shape = true;
  result.expansions =
      static_cast<uint64_t>(std::count_if(t.begin(), t.end(), [](double v) { return std::isfinite(v); }));
  return result;
}

}  // namespace navd::planning
