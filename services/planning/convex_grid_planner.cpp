#include "services/planning/convex_grid_planner.h"

#include <cmath>
#include <limits>
#include <queue>
#include <random>

#include "services/common/error.h"

namespace navd::planning {
namespace {

// "A large penalty, effectively rendering that path useless" (seed 000): metres.
constexpr double kObstaclePenalty = 1e4;

struct Search {
  std::vector<double> cost;   // metres from the start along waypoints (penalties included)
  std::vector<Point2> entry;  // the waypoint a cell was entered through
  std::vector<int32_t> parent;
};

}  // namespace

ConvexGridPath PlanOnConvexGrid(const ConvexCellMap& grid, const Costmap& costmap, const Point2& start,
                                const Point2& goal, const ConvexGridOptions& o,
                                const std::vector<MovingObstacleCircle>& obstacles, const StopRequested& stop) {
  if (o.iterations < 1) throw Error(ErrorCode::kInvalidArgument, "iterations must be >= 1");
  if (!(o.waypoint_spacing > 0.0)) throw Error(ErrorCode::kInvalidArgument, "waypoint_spacing must be > 0 metres");
  const CellEntry from = grid.Enter(costmap, start, o.entry_reach, "start");
  const CellEntry to = grid.Enter(costmap, goal, o.entry_reach, "goal");

  // Only obstacles the robot has seen near it count (seed: closer than Δ).
  std::vector<MovingObstacleCircle> near;
  for (const auto& ob : obstacles)
    if (Distance(ob.centre, start) < o.obstacle_range) near.push_back({ob.centre, ob.radius + o.obstacle_margin});
  auto penalty = [&](const Point2& a, const Point2& b) {
    for (const auto& ob : near)
      if (DistanceToSegment(ob.centre, a, b) < ob.radius) return kObstaclePenalty;
    return 0.0;
  };

  const auto& cells = grid.cells();
  const auto& doors = grid.doorways();
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> along(0.0, 1.0);
  ConvexGridPath best;
  double best_cost = std::numeric_limits<double>::infinity();
  Search s;
  std::vector<Point2> waypoint(doors.size());
  for (int iteration = 0; iteration < o.iterations; ++iteration) {
    // One random waypoint per shared side for this iteration.
    for (size_t d = 0; d < doors.size(); ++d) waypoint[d] = grid.DoorwayPoint(static_cast<int32_t>(d), along(rng));
    s.cost.assign(cells.size(), std::numeric_limits<double>::infinity());
    s.entry.assign(cells.size(), Point2::Zero());
    s.parent.assign(cells.size(), -1);
    std::vector<int32_t> door_in(cells.size(), -1);
    using Item = std::pair<double, int32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    s.cost[from.cell] = 0.0;
    s.entry[from.cell] = from.point;
    open.push({0.0, from.cell});
    double goal_cost = std::numeric_limits<double>::infinity();
    while (!open.empty()) {
      const auto [c_cost, c] = open.top();
      open.pop();
      if (c_cost > s.cost[c]) continue;
      if (c_cost >= goal_cost) break;  // nothing left can reach the goal more cheaply
      if ((++best.expansions & 255) == 0 && stop && stop())
        throw Error(ErrorCode::kDeadlineExceeded, "convex grid planning stopped: deadline exceeded or cancelled");
      if (c == to.cell) {
        goal_cost = std::min(goal_cost, c_cost + Distance(s.entry[c], to.point) + penalty(s.entry[c], to.point));
        continue;
      }
      for (const int32_t d : cells[c].doorways) {
        const int32_t n = doors[d].other(c);
        const Point2& q = waypoint[d];
        const double cost = c_cost + Distance(s.entry[c], q) + penalty(s.entry[c], q);
        if (cost < s.cost[n]) {
          s.cost[n] = cost;
          s.entry[n] = q;
          s.parent[n] = c;
          door_in[n] = d;
          open.push({cost, n});
        }
      }
    }
    if (std::isfinite(goal_cost) && goal_cost < best_cost) {
      best_cost = goal_cost;
      std::vector<Point2> way{to.point};
      for (int32_t c = to.cell; c != from.cell; c = s.parent[c]) {
        const auto [leave, enter] = grid.Crossing(door_in[c], s.parent[c], s.entry[c]);
        way.push_back(enter);
        way.push_back(leave);
      }
      way.push_back(from.point);
      best.points.assign(way.rbegin(), way.rend());
    }
    best.best_length_per_iteration.push_back(best_cost);
  }
  if (best.points.empty())
    throw Error(ErrorCode::kNotFound,
                "no path: the goal's cell of the convex navigation grid cannot be reached from the start's");

  // The entries off the grid (start or goal in the margin) are joined straight.
  std::vector<Point2> way;
  if (from.point != start) way.push_back(start);
  way.insert(way.end(), best.points.begin(), best.points.end());
  if (to.point != goal) way.push_back(goal);
  // Interpolation to at most d_wp between waypoints.
  best.points = {way.front()};
  best.length = 0.0;
  best.penalised = false;
  for (size_t i = 1; i < way.size(); ++i) {
    const double len = Distance(way[i - 1], way[i]);
    if (len <= 0.0) continue;
    best.length += len;
    best.penalised = best.penalised || penalty(way[i - 1], way[i]) > 0.0;
    const int parts = std::max(1, static_cast<int>(std::ceil(len / o.waypoint_spacing - 1e-9)));
    for (int k = 1; k <= parts; ++k) best.points.emplace_back(way[i - 1] + (way[i] - way[i - 1]) * (double(k) / parts));
  }
  return best;
}

std::vector<PlannerOptionSpec> ConvexGridPlanner::options() const {
  return {{"margin", 0.05, "metres of contraction beyond the costmap's inflation (seed's μ minus the robot radius)"},
          {"iterations", 10, "n: searches with fresh random side waypoints; the shortest path is kept (>= 1)"},
          {"waypoint_spacing", 0.5, "d_wp: metres between interpolated waypoints (> 0)"},
          {"seed", 1, "random seed of the side waypoints"}};
}

CellPath ConvexGridPlanner::Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                                 const PlannerOptions& options, const StopRequested& stop) const {
  return PlanInScene(costmap, start, goal, options, {}, stop);
}

CellPath ConvexGridPlanner::PlanInScene(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                                        const PlannerOptions& options, const PlanningScene& scene,
                                        const StopRequested& stop) const {
  const double iterations = options.at("iterations"), seed = options.at("seed");
  if (!(iterations >= 1 && iterations <= 10000))
    throw Error(ErrorCode::kInvalidArgument, "iterations must be in 1..10000");
  if (!(seed >= 0 && seed < 1e18)) throw Error(ErrorCode::kInvalidArgument, "seed must be a number >= 0");
  const auto grid = cells_->Get(costmap, options.at("margin"));
  ConvexGridOptions o;
  o.iterations = static_cast<int>(iterations);
  o.waypoint_spacing = options.at("waypoint_spacing");
  o.seed = static_cast<uint64_t>(seed);
  std::vector<MovingObstacleCircle> obstacles;
  for (const MovingBody& b : scene.moving) obstacles.push_back({b.position, b.radius});
  const ConvexGridPath path = PlanOnConvexGrid(*grid, costmap, costmap.grid().CellCenter(start),
                                               costmap.grid().CellCenter(goal), o, obstacles, stop);
  CellPath result;
  result.cells = {start, goal};
  result.points = path.points;
  result.keep_shape = true;  // the seed's waypoints at d_wp are the output
  result.expansions = path.expansions;
  return result;
}

}  // namespace navd::planning
