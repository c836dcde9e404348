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

// The grid as exploration searches it: a cell index, its neighbours, and the cells a robot may
// stand on (known free, clear of obstacles by the clearance).
struct SearchGrid {
  const OccupancyGrid& map;
  int w, h;
  size_t n;
  std::vector<uint8_t> traversable;

  bool Inside(int x, int y) const { return x >= 0 && y >= 0 && x < w && y < h; }
  Point2 Centre(int32_t i) const { return map.CellCenter({i % w, i / w}); }
  // The 8-connected step from cell (x, y) in direction k to v is allowed: no corner cutting.
  bool CanStep(int x, int y, int k, int32_t v) const {
    const int nx = x + kDx[k], ny = y + kDy[k];
    return traversable[v] && (k < 4 || (traversable[y * w + nx] && traversable[ny * w + x]));
  }
};

// The robot's cell, or, when the robot stands in the clearance zone, the nearest traversable cell
// it reaches within a metre through known free space (never one beyond a wall); -1 when none.
int32_t StartCell(const SearchGrid& g, int32_t s, const ExplorationOptions& o) {
  if (g.traversable[s]) return s;
  const auto& cells = g.map.cells();
  std::vector<double> reach(g.n, kInf);
  std::queue<int32_t> q;
  reach[s] = 0.0;
  q.push(s);
  while (!q.empty()) {
    const int32_t u = q.front();
    q.pop();
    if (g.traversable[u]) return u;
    const int x = u % g.w, y = u / g.w;
    for (int k = 0; k < 4; ++k) {
      const int nx = x + kDx[k], ny = y + kDy[k];
      if (!g.Inside(nx, ny)) continue;
      const int32_t v = ny * g.w + nx;
      const double d = reach[u] + g.map.resolution();
      if (d > 1.0 || reach[v] <= d || cells[v] < 0 || cells[v] >= o.free_below) continue;
      reach[v] = d;
      q.push(v);
    }
  }
  return -1;
}

// Dijkstra over traversable cells from `s` (8-connected, no corner cutting; the greedy method
// pays more for cells more likely occupied): the distance to each cell, and its parent.
void ShortestPaths(const SearchGrid& g, int32_t s, ExplorationMethod method, const ExplorationOptions& o,
                   std::vector<double>& dist, std::vector<int32_t>& parent) {
  const auto& cells = g.map.cells();
  dist.assign(g.n, kInf);
  parent.assign(g.n, -1);
  using Item = std::pair<double, int32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  dist[s] = 0.0;
  open.push({0.0, s});
  while (!open.empty()) {
    const auto [d, u] = open.top();
    open.pop();
    if (d > dist[u]) continue;
    const int x = u % g.w, y = u / g.w;
    for (int k = 0; k < 8; ++k) {
      const int nx = x + kDx[k], ny = y + kDy[k];
      if (!g.Inside(nx, ny)) continue;
      const int32_t v = ny * g.w + nx;
      if (!g.CanStep(x, y, k, v)) continue;
      double step = (k >= 4 ? M_SQRT2 : 1.0) * g.map.resolution();
      if (method == ExplorationMethod::kGreedy) step *= 1.0 + o.occupancy_cost * cells[v] / 100.0;
      if (d + step < dist[v]) {
        dist[v] = d + step;
        parent[v] = u;
        open.push({dist[v], v});
      }
    }
  }
}

// Reachable frontier cells: traversable at the full clearance, next to unknown space, outside the
// excluded places.
std::vector<int32_t> ReachableFrontier(const SearchGrid& g, const DistanceField& obstacles,
                                       const std::vector<double>& dist, const ExplorationOptions& o) {
  const auto& cells = g.map.cells();
  std::vector<int32_t> frontier;
  for (size_t i = 0; i < g.n; ++i) {
    if (!std::isfinite(dist[i]) || obstacles.values()[i] <= o.clearance) continue;
    const int x = static_cast<int>(i % g.w), y = static_cast<int>(i / g.w);
    bool excluded = false;
    for (const Point2& e : o.excluded)
      excluded = excluded || Distance(g.map.CellCenter({x, y}), e) < o.exclusion_radius;
    if (excluded) continue;
    for (int k = 0; k < 4; ++k) {
      const int nx = x + kDx[k], ny = y + kDy[k];
      if (g.Inside(nx, ny) && cells[static_cast<size_t>(ny) * g.w + nx] < 0) {
        frontier.push_back(static_cast<int32_t>(i));
        break;
      }
    }
  }
  return frontier;
}

// The frontier method's goal: the frontier cells grouped (8-connected) into frontiers, the nearest
// frontier of at least min_frontier_cells (aimed at its member nearest its centre: the robot
// looks into the opening from there), else the largest small one; -1 when none.
int32_t NearestFrontierGoal(const SearchGrid& g, const std::vector<int32_t>& frontier, const std::vector<double>& dist,
                            const ExplorationOptions& o) {
  std::vector<int32_t> label(g.n, -1);
  std::vector<uint8_t> is_frontier(g.n, 0);
  for (int32_t f : frontier) is_frontier[f] = 1;
  double best = kInf;
  int32_t goal = -1, best_small = -1;
  size_t best_small_size = 0;
  int clusters = 0;
  for (int32_t f : frontier) {
    if (label[f] >= 0) continue;
    std::vector<int32_t> members{f};
    label[f] = clusters;
    for (size_t k = 0; k < members.size(); ++k) {
      const int x = members[k] % g.w, y = members[k] / g.w;
      for (int j = 0; j < 8; ++j) {
        const int nx = x + kDx[j], ny = y + kDy[j];
        if (!g.Inside(nx, ny)) continue;
        const int32_t v = ny * g.w + nx;
        if (is_frontier[v] && label[v] < 0) {
          label[v] = clusters;
          members.push_back(v);
        }
      }
    }
    ++clusters;
    Point2 centre = Point2::Zero();
    for (int32_t m : members) centre += g.Centre(m);
    centre /= static_cast<double>(members.size());
    const int32_t aim = *std::min_element(members.begin(), members.end(), [&](int32_t a, int32_t b) {
      return Distance(g.Centre(a), centre) < Distance(g.Centre(b), centre);
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
  return goal >= 0 ? goal : best_small;
}

// Voronoi Fast Marching's goal: the frontier cell of the highest WV, W the obstacles' distance
// transform (unknown space counts as free), VT the visited places'.
int32_t VoronoiGoal(const SearchGrid& g, const DistanceField& obstacles, const std::vector<int32_t>& frontier,
                    const std::vector<Point2>& visited, const ExplorationOptions& o) {
  OccupancyGrid trail(g.w, g.h, g.map.resolution(), g.map.origin(), OccupancyGrid::kFree);
  for (const Point2& p : visited) {
    const CellIndex c = g.map.CellOf(p);
    if (g.map.Contains(c)) trail.set(c, OccupancyGrid::kOccupied);
  }
  const DistanceField visited_field(trail, false);
  double best = -kInf;
  int32_t goal = -1;
  for (int32_t f : frontier) {
    const double W = std::min(1.0, obstacles.values()[f] / o.w_saturation);
    const double VT = visited.empty() ? 1.0 : std::min(1.0, visited_field.values()[f] / o.vt_saturation);
    const double wv = 0.5 * VT + W;
    if (wv > best) {
      best = wv;
      goal = f;
    }
  }
  return goal;
}

// Fast Marching from `goal` over the speed WV (slow near walls), then steepest descent from `s`:
// the cell centres, or nothing when the descent stalls.
std::vector<Point2> FastMarchingPath(const SearchGrid& g, const DistanceField& obstacles, int32_t s, int32_t goal,
                                     const ExplorationOptions& o) {
  std::vector<double> speed(g.n, 0.0);
  for (size_t i = 0; i < g.n; ++i)
    if (g.traversable[i]) speed[i] = std::max(0.05, std::min(1.0, obstacles.values()[i] / o.w_saturation));
  const std::vector<double> t = planning::FastMarch(g.w, g.h, g.map.resolution(), speed, {goal % g.w, goal / g.w});
  std::vector<Point2> path;
  int32_t u = s;
  path.push_back(g.Centre(u));
  for (size_t guard = 0; u != goal && guard < g.n; ++guard) {
    int32_t next = -1;
    double best = t[u];
    const int x = u % g.w, y = u / g.w;
    for (int k = 0; k < 8; ++k) {
      const int nx = x + kDx[k], ny = y + kDy[k];
      if (!g.Inside(nx, ny)) continue;
      const int32_t v = ny * g.w + nx;
      if (g.CanStep(x, y, k, v) && t[v] < best) {
        best = t[v];
        next = v;
      }
    }
    if (next < 0) break;
    u = next;
    path.push_back(g.Centre(u));
  }
  if (u != goal) path.clear();
  return path;
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
  const size_t n = static_cast<size_t>(map.width()) * map.height();
  const auto& cells = map.cells();
  const DistanceField obstacles(map, false);
  SearchGrid g{map, map.width(), map.height(), n, std::vector<uint8_t>(n)};
  for (size_t i = 0; i < n; ++i)
    g.traversable[i] = cells[i] >= 0 && cells[i] < o.free_below && obstacles.values()[i] > o.clearance;
  if (!o.squeeze_trail.empty()) {
    OccupancyGrid trail(g.w, g.h, map.resolution(), map.origin(), OccupancyGrid::kFree);
    const std::vector<Point2>& t = o.squeeze_trail;
    for (size_t k = 0; k < t.size(); ++k)  // each segment; the last point alone
      TraverseSegment(map, t[k], t[std::min(k + 1, t.size() - 1)], [&](const CellIndex& c, double) {
        if (trail.Contains(c)) trail.set(c, OccupancyGrid::kOccupied);
        return true;
      });
    const DistanceField near_trail(trail, false);
    for (size_t i = 0; i < n; ++i)
      g.traversable[i] = g.traversable[i] ||
                         (cells[i] >= 0 && cells[i] < o.free_below && obstacles.values()[i] > o.squeeze_clearance &&
                          near_trail.values()[i] <= o.squeeze_radius);
  }
  const CellIndex robot_cell = map.CellOf(robot.translation());
  if (!map.Contains(robot_cell)) return std::nullopt;
  const int32_t s = StartCell(g, static_cast<int32_t>(map.Flat(robot_cell)), o);
  if (s < 0) return std::nullopt;
  std::vector<double> dist;
  std::vector<int32_t> parent;
  ShortestPaths(g, s, method, o, dist, parent);
  const std::vector<int32_t> frontier = ReachableFrontier(g, obstacles, dist, o);
  if (frontier.empty()) return std::nullopt;

  int32_t goal = -1;
  if (method == ExplorationMethod::kGreedy) {
    goal = *std::min_element(frontier.begin(), frontier.end(), [&](int32_t a, int32_t b) { return dist[a] < dist[b]; });
  } else if (method == ExplorationMethod::kFrontier) {
    goal = NearestFrontierGoal(g, frontier, dist, o);
  } else {
    goal = VoronoiGoal(g, obstacles, frontier, visited, o);
  }
  if (goal < 0) return std::nullopt;

  std::vector<Point2> cells_path;
  if (method == ExplorationMethod::kVoronoiFastMarching) cells_path = FastMarchingPath(g, obstacles, s, goal, o);
  if (cells_path.empty()) {  // the Dijkstra path, also where the descent stalled
    for (int32_t u = goal; u >= 0; u = parent[u]) cells_path.push_back(g.Centre(u));
    std::reverse(cells_path.begin(), cells_path.end());
  }
  ExplorationStep step;
  step.goal = g.Centre(goal);
  step.frontier_cells = static_cast<int>(frontier.size());
  step.path = Shorten(map, g.traversable, cells_path);
  if (step.path.size() == 1) step.path.push_back(step.path.front());
  step.path.front() = robot.translation();
  return step;
}

}  // namespace navd::navigation
