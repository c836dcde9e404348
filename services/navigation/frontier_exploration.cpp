#include "services/navigation/frontier_exploration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "services/common/distance_field.h"
#include "services/common/error.h"
#include "services/common/grid_traversal.h"
#include "services/planning/voronoi_fast_marching_planner.h"

namespace navd::navigation {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};

// Whether the straight segment a-b crosses only traversable cells.
bool Clear(const OccupancyGrid& map, const std::vector<uint8_t>& traversable, const Point2& a, const Point2& b) {
  bool clear = true;
  TraverseSegment(map, a, b, [&](const CellIndex& c, double) {
    clear = map.Contains(c) && traversable[map.Flat(c)];
    return clear;
  });
  return clear;
}

// Greedy line-of-sight shortening of a cell path.
std::vector<Point2> Shorten(const OccupancyGrid& map, const std::vector<uint8_t>& traversable,
                            const std::vector<Point2>& points) {
  if (points.size() <= 2) return points;
  std::vector<Point2> out{points.front()};
  size_t anchor = 0;
  while (anchor + 1 < points.size()) {
    size_t next = anchor + 1;
    while (next + 1 < points.size() && Clear(map, traversable, points[anchor], points[next + 1])) ++next;
    out.push_back(points[next]);
    anchor = next;
  }
  return out;
}

}  // namespace

ExplorationMethod ParseExplorationMethod(const std::string& name) {
  if (name == "greedy") return ExplorationMethod::kGreedy;
  if (name == "frontier") return ExplorationMethod::kFrontier;
  if (name == "vfm") return ExplorationMethod::kVoronoiFastMarching;
  throw Error(ErrorCode::kInvalidArgument,
              "method: unknown exploration method '" + name + "' (known: greedy, frontier, vfm)");
}

std::optional<ExplorationStep> NextExplorationStep(const OccupancyGrid& map, const Pose2& robot,
                                                   ExplorationMethod method, const std::vector<Point2>& visited,
                                                   const ExplorationOptions& o) {
  const int w = map.width(), h = map.height();
  const size_t n = static_cast<size_t>(w) * h;
  const auto& cells = map.cells();
  const DistanceField obstacles(map, false);
  std::vector<uint8_t> traversable(n);
  for (size_t i = 0; i < n; ++i)
    traversable[i] = cells[i] >= 0 && cells[i] < o.free_below && obstacles.values()[i] > o.clearance;

  // Start from the robot's cell, or, when the robot stands in the clearance zone, from the nearest
  // traversable cell it reaches within a metre through known free space (never one beyond a wall).
  const CellIndex robot_cell = map.CellOf(robot.translation());
  if (!map.Contains(robot_cell)) return std::nullopt;
  int32_t s = static_cast<int32_t>(map.Flat(robot_cell));
  if (!traversable[s]) {
    std::vector<double> reach(n, kInf);
    std::queue<int32_t> q;
    reach[s] = 0.0;
    q.push(s);
    s = -1;
    while (!q.empty() && s < 0) {
      const int32_t u = q.front();
      q.pop();
      if (traversable[u]) {
        s = u;
        break;
      }
      const int x = u % w, y = u / w;
      for (int k = 0; k < 4; ++k) {
        const int nx = x + kDx[k], ny = y + kDy[k];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        const int32_t v = ny * w + nx;
        const double d = reach[u] + map.resolution();
        if (d > 1.0 || reach[v] <= d || cells[v] < 0 || cells[v] >= o.free_below) continue;
        reach[v] = d;
        q.push(v);
      }
    }
    if (s < 0) return std::nullopt;
  }
  std::vector<double> dist(n, kInf);
  std::vector<int32_t> parent(n, -1);
  using Item = std::pair<double, int32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  dist[s] = 0.0;
  open.push({0.0, s});

  // Dijkstra over traversable cells (8-connected, no corner cutting).
  while (!open.empty()) {
    const auto [d, u] = open.top();
    open.pop();
    if (d > dist[u]) continue;
    const int x = u % w, y = u / w;
    for (int k = 0; k < 8; ++k) {
      const int nx = x + kDx[k], ny = y + kDy[k];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
      const int32_t v = ny * w + nx;
      if (!traversable[v]) continue;
      if (k >= 4 && (!traversable[y * w + nx] || !traversable[ny * w + x])) continue;
      double step = (k >= 4 ? M_SQRT2 : 1.0) * map.resolution();
      if (method == ExplorationMethod::kGreedy) step *= 1.0 + o.occupancy_cost * cells[v] / 100.0;
      if (d + step < dist[v]) {
        dist[v] = d + step;
        parent[v] = u;
        open.push({dist[v], v});
      }
    }
  }

  // Reachable frontier cells: traversable, next to unknown space.
  std::vector<int32_t> frontier;
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(dist[i])) continue;
    const int x = static_cast<int>(i % w), y = static_cast<int>(i / w);
    bool excluded = false;
    for (const Point2& e : o.excluded) excluded = excluded || Distance(map.CellCenter({x, y}), e) < o.exclusion_radius;
    if (excluded) continue;
    for (int k = 0; k < 4; ++k) {
      const int nx = x + kDx[k], ny = y + kDy[k];
      if (nx >= 0 && ny >= 0 && nx < w && ny < h && cells[static_cast<size_t>(ny) * w + nx] < 0) {
        frontier.push_back(static_cast<int32_t>(i));
        break;
      }
    }
  }
  if (frontier.empty()) return std::nullopt;

  int32_t goal = -1;
  if (method == ExplorationMethod::kGreedy) {
    goal = *std::min_element(frontier.begin(), frontier.end(), [&](int32_t a, int32_t b) { return dist[a] < dist[b]; });
  } else if (method == ExplorationMethod::kFrontier) {
    // Group the frontier cells (8-connected) into frontiers.
    std::vector<int32_t> label(n, -1);
    std::vector<uint8_t> is_frontier(n, 0);
    for (int32_t f : frontier) is_frontier[f] = 1;
    double best = kInf;
    int32_t best_small = -1;
    size_t best_small_size = 0;
    int clusters = 0;
    for (int32_t f : frontier) {
      if (label[f] >= 0) continue;
      std::vector<int32_t> members{f};
      label[f] = clusters;
      for (size_t k = 0; k < members.size(); ++k) {
        const int x = members[k] % w, y = members[k] / w;
        for (int j = 0; j < 8; ++j) {
          const int nx = x + kDx[j], ny = y + kDy[j];
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          const int32_t v = ny * w + nx;
          if (is_frontier[v] && label[v] < 0) {
            label[v] = clusters;
            members.push_back(v);
          }
        }
      }
      ++clusters;
      // The member nearest the frontier's centre: the robot looks into the opening from there.
      Point2 centre = Point2::Zero();
      for (int32_t m : members) centre += map.CellCenter({m % w, m / w});
      centre /= static_cast<double>(members.size());
      const int32_t aim = *std::min_element(members.begin(), members.end(), [&](int32_t a, int32_t b) {
        return Distance(map.CellCenter({a % w, a / w}), centre) < Distance(map.CellCenter({b % w, b / w}), centre);
      });
      if (static_cast<int>(members.size()) >= o.min_frontier_cells) {
        if (dist[aim] < best) {
          best = dist[aim];
          goal = aim;
        }
      } else if (members.size() > best_small_size) {
        best_small_size = members.size();
        best_small = aim;
      }
    }
    if (goal < 0) goal = best_small;  // only small frontiers left: the largest of them
  } else {
    // W: the obstacles' transform (unknown space counts as free); VT: the visited places'.
    OccupancyGrid trail(w, h, map.resolution(), map.origin(), OccupancyGrid::kFree);
    for (const Point2& p : visited) {
      const CellIndex c = map.CellOf(p);
      if (map.Contains(c)) trail.set(c, OccupancyGrid::kOccupied);
    }
    const DistanceField visited_field(trail, false);
    double best = -kInf;
    for (int32_t f : frontier) {
      const double W = std::min(1.0, obstacles.values()[f] / o.w_saturation);
      const double VT = visited.empty() ? 1.0 : std::min(1.0, visited_field.values()[f] / o.vt_saturation);
      const double wv = 0.5 * VT + W;
      if (wv > best) {
        best = wv;
        goal = f;
      }
    }
  }
  if (goal < 0) return std::nullopt;

  std::vector<Point2> cells_path;
  if (method == ExplorationMethod::kVoronoiFastMarching) {
    // Fast Marching from the goal over the speed WV (slow near walls), then steepest descent.
    std::vector<double> speed(n, 0.0);
    for (size_t i = 0; i < n; ++i)
      if (traversable[i]) speed[i] = std::max(0.05, std::min(1.0, obstacles.values()[i] / o.w_saturation));
    const std::vector<double> t = planning::FastMarch(w, h, map.resolution(), speed, {goal % w, goal / w});
    int32_t u = s;
    cells_path.push_back(map.CellCenter({u % w, u / w}));
    for (size_t guard = 0; u != goal && guard < n; ++guard) {
      int32_t next = -1;
      double best = t[u];
      const int x = u % w, y = u / w;
      for (int k = 0; k < 8; ++k) {
        const int nx = x + kDx[k], ny = y + kDy[k];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        const int32_t v = ny * w + nx;
        if (!traversable[v] || (k >= 4 && (!traversable[y * w + nx] || !traversable[ny * w + x]))) continue;
        if (t[v] < best) {
          best = t[v];
          next = v;
        }
      }
      if (next < 0) break;  // no descent: fall back to the Dijkstra path below
      u = next;
      cells_path.push_back(map.CellCenter({u % w, u / w}));
    }
    if (u != goal) cells_path.clear();
  }
  if (cells_path.empty()) {
    for (int32_t u = goal; u >= 0; u = parent[u]) cells_path.push_back(map.CellCenter({u % w, u / w}));
    std::reverse(cells_path.begin(), cells_path.end());
  }
  ExplorationStep step;
  step.goal = map.CellCenter({goal % w, goal / w});
  step.frontier_cells = static_cast<int>(frontier.size());
  step.path = Shorten(map, traversable, cells_path);
  if (step.path.size() == 1) step.path.push_back(step.path.front());
  step.path.front() = robot.translation();
  return step;
}

}  // namespace navd::navigation
