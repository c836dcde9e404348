#include "services/planning/planning_engine.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include "services/common/error.h"
#include "services/planning/elastic_band.h"

namespace navd::planning {
namespace {

const std::vector<PlannerOptionSpec>& CommonOptions() {
  static const std::vector<PlannerOptionSpec> kCommon = {
      {"smooth", 1.0, "1: shorten the path by line-of-sight shortcuts on the costmap, 0: raw cell path"},
      {"elastic_band", 0.0,
       "1: then relax it as an elastic band (book ch. 9 R-snake: contraction, curvature, obstacle forces)"}};
  return kCommon;
}

void CheckFinite(const Point2& p, const std::string& field) {
  if (!std::isfinite(p.x())) throw Error(ErrorCode::kInvalidArgument, field + ".x is not a finite number");
  if (!std::isfinite(p.y())) throw Error(ErrorCode::kInvalidArgument, field + ".y is not a finite number");
}

// Every number of the request finite, and every moving body's radius a number of metres.
void CheckRequest(const Point2& start, const Point2& goal, const PlanningScene& scene) {
  CheckFinite(start, "start");
  CheckFinite(goal, "goal");
  for (size_t i = 0; i < scene.moving.size(); ++i) {
    const std::string field = "moving[" + std::to_string(i) + "]";
    CheckFinite(scene.moving[i].position, field + ".position");
    CheckFinite(scene.moving[i].velocity, field + ".velocity");
    if (!(scene.moving[i].radius >= 0.0 && scene.moving[i].radius < 1e3))
      throw Error(ErrorCode::kInvalidArgument, field + ".radius must be a number of metres >= 0");
  }
  for (size_t i = 0; i < scene.obstacle_cells.size(); ++i)
    CheckFinite(scene.obstacle_cells[i], "obstacle_cells[" + std::to_string(i) + "]");
}

void CheckInsideMap(const OccupancyGrid& grid, const Point2& p, const std::string& field) {
  if (!grid.ContainsPoint(p)) {
    throw Error(ErrorCode::kInvalidArgument, field + " " + FormatPoint(p) + " is outside the map, which spans " +
                                                 FormatPoint(grid.origin()) + " to " +
                                                 FormatPoint(grid.origin() + Point2(grid.size_x(), grid.size_y())));
  }
}

// The goal's cell, where the robot can stand: not in an obstacle nor within its inflation.
CellIndex GoalCell(const Costmap& costmap, const Point2& goal) {
  const CellIndex goal_cell = costmap.grid().CellOf(goal);
  if (costmap.grid().IsOccupied(goal_cell)) {
    throw Error(ErrorCode::kInvalidArgument, "goal " + FormatPoint(goal) + " is inside an obstacle");
  }
  if (costmap.IsLethal(goal_cell)) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", costmap.options().inflation_radius);
    throw Error(ErrorCode::kInvalidArgument, "goal " + FormatPoint(goal) + " is within " + buf +
                                                 " m of an obstacle or unknown space: the robot cannot stand there");
  }
  return goal_cell;
}

// The start's cell; a start within the inflation (a robot brushing a wall) leaves it by the
// nearest free cell within `recovery_radius` metres.
CellIndex StartCell(const Costmap& costmap, const Point2& start, double recovery_radius) {
  const OccupancyGrid& grid = costmap.grid();
  const CellIndex start_cell = grid.CellOf(start);
  if (grid.IsOccupied(start_cell)) {
    throw Error(ErrorCode::kInvalidArgument, "start " + FormatPoint(start) + " is inside an obstacle");
  }
  if (!costmap.IsLethal(start_cell)) return start_cell;
  const std::optional<CellIndex> free =
      costmap.NearestFree(start_cell, static_cast<int>(recovery_radius / grid.resolution()), false);
  if (!free) {
    char buf[96];
    std::snprintf(buf, sizeof buf,
                  " is within %.2f m of an obstacle or unknown space, and no free cell is within %.2f m",
                  costmap.options().inflation_radius, recovery_radius);
    throw Error(ErrorCode::kInvalidArgument, "start " + FormatPoint(start) + buf);
  }
  return *free;
}

// The path's points: the cells' (or the planner's own points), joined to the exact start and goal,
// then shortened and relaxed as the options ask. `recovered`: the start left the inflation first.
std::vector<Point2> PathPoints(const Costmap& costmap, const CellPath& cells, const Point2& start, const Point2& goal,
                               bool recovered, const PlannerOptions& options, const StopRequested& stop) {
  const OccupancyGrid& grid = costmap.grid();
  // The end cells' own centres are dropped when the exact points see their neighbours directly
  // (always for grid steps; any-angle planners checked visibility from the centres only).
  std::vector<Point2> points{start};
  if (!cells.points.empty()) {
    points.insert(points.end(), cells.points.begin(), cells.points.end());
  } else {
    for (const CellIndex& c : cells.cells) points.push_back(grid.CellCenter(c));
  }
  points.push_back(goal);
  if (!cells.keep_shape && points.size() > 3 && costmap.SegmentFree(points[points.size() - 3], goal)) {
    points.erase(points.end() - 2);
  }
  if (!cells.keep_shape && !recovered && points.size() > 2 && costmap.SegmentFree(start, points[2])) {
    points.erase(points.begin() + 1);
  }
  if (options.at("smooth") != 0.0 && !cells.keep_shape) {
    // The first hop may leave the inflation zone, which the shortcut test would reject; keep it.
    if (recovered) {
      std::vector<Point2> rest(points.begin() + 1, points.end());
      rest = ShortcutPath(costmap, rest, stop);
      points.resize(1);
      points.insert(points.end(), rest.begin(), rest.end());
    } else {
      points = ShortcutPath(costmap, points, stop);
    }
  }
  if (options.at("elastic_band") != 0.0 && !cells.keep_shape && cells.speed_limits.empty()) {
    points = ElasticBand(costmap, points);
  }
  return points;
}

}  // namespace

double PathLength(const std::vector<Point2>& points) {
  double len = 0;
  for (size_t i = 1; i < points.size(); ++i) len += Distance(points[i - 1], points[i]);
  return len;
}

std::vector<Point2> ShortcutPath(const Costmap& costmap, const std::vector<Point2>& points, const StopRequested& stop) {
  if (points.size() <= 2) return points;
  std::vector<Point2> out{points.front()};
  size_t anchor = 0;
  while (anchor < points.size() - 1) {
    // Extend the segment while the next point stays visible: each check costs the segment's
    // length, so the whole pass is linear in path length times segment length, never quadratic
    // in the number of points.
    // With a decay layer a shortcut may not run closer to obstacles (higher cost) than the stretch
    // of path it replaces, so smoothing keeps the clearance cost-aware planners chose.
    size_t next = anchor + 1;
    const bool costs = costmap.cost_data() != nullptr;
    int replaced_max = costs ? costmap.SegmentMaxCost(points[anchor], points[next]) : 0;
    while (next + 1 < points.size()) {
      if (!costs) {
        if (!costmap.SegmentFree(points[anchor], points[next + 1])) break;
      } else {
        const int stretch = std::max(replaced_max, costmap.SegmentMaxCost(points[next], points[next + 1]));
        const int shortcut = costmap.SegmentMaxCost(points[anchor], points[next + 1]);
        if (shortcut < 0 || shortcut > stretch) break;
        replaced_max = stretch;
      }
      ++next;
    }
    if (stop && stop()) {
      throw Error(ErrorCode::kDeadlineExceeded, "path smoothing stopped: deadline exceeded or cancelled");
    }
    out.push_back(points[next]);
    anchor = next;
  }
  return out;
}

PlanningEngine::PlanningEngine(const MapStore& maps, PlanningEngineOptions options)
    : maps_(maps), options_(std::move(options)), costmap_options_(options_.costmap) {}

void PlanningEngine::Register(std::unique_ptr<GlobalPlanner> planner) { planners_.push_back(std::move(planner)); }

std::vector<PlannerInfo> PlanningEngine::Planners() const {
  std::vector<PlannerInfo> out;
  for (const auto& p : planners_) {
    PlannerInfo info{p->name(),      p->description(),  p->options(), p->name() == options_.default_planner,
                     p->objective(), p->time_budgeted()};
    info.options.insert(info.options.end(), CommonOptions().begin(), CommonOptions().end());
    out.push_back(std::move(info));
  }
  return out;
}

bool PlanningEngine::PlansBriefly(const std::string& name) const {
  const std::string& wanted = name.empty() ? options_.default_planner : name;
  for (const auto& p : planners_)
    if (p->name() == wanted) return !p->time_budgeted();
  return true;
}

const GlobalPlanner& PlanningEngine::Find(const std::string& name) const {
  const std::string wanted = name.empty() ? options_.default_planner : name;
  std::string known;
  for (const auto& p : planners_) {
    if (p->name() == wanted) return *p;
    known += (known.empty() ? "" : ", ") + p->name();
  }
  throw Error(ErrorCode::kInvalidArgument, "planner: unknown planner '" + wanted + "' (known: " + known + ")");
}

PlannerOptions PlanningEngine::ResolveOptions(const GlobalPlanner& planner,
                                              const std::map<std::string, double>& given) const {
  PlannerOptions resolved;
  auto specs = planner.options();
  specs.insert(specs.end(), CommonOptions().begin(), CommonOptions().end());
  for (const auto& s : specs) resolved[s.name] = s.default_value;
  for (const auto& [name, value] : given) {
    if (!resolved.count(name)) {
      throw Error(ErrorCode::kInvalidArgument,
                  "options: planner '" + planner.name() + "' has no option '" + name + "'");
    }
    if (!std::isfinite(value)) throw Error(ErrorCode::kInvalidArgument, "options: '" + name + "' is not finite");
    if ((name == "smooth" || name == "elastic_band") && value != 0.0 && value != 1.0) {
      throw Error(ErrorCode::kInvalidArgument, "options: '" + name + "' must be 0 or 1");
    }
    resolved[name] = value;
  }
  return resolved;
}

void PlanningEngine::SetInflationRadius(double radius) {
  if (!(radius >= 0.0) || !std::isfinite(radius))
    throw Error(ErrorCode::kInvalidArgument, "inflation radius must be a non-negative number of metres");
  std::lock_guard<std::mutex> lock(costmap_mutex_);
  if (costmap_options_.inflation_radius == radius) return;
  costmap_options_.inflation_radius = radius;
  costmap_.reset();  // the next request builds it with the new radius
}

double PlanningEngine::inflation_radius() const {
  std::lock_guard<std::mutex> lock(costmap_mutex_);
  return costmap_options_.inflation_radius;
}

std::shared_ptr<const Costmap> PlanningEngine::CurrentCostmap() {
  auto snapshot = maps_.Get();
  if (!snapshot) throw Error(ErrorCode::kFailedPrecondition, "no map is loaded");
  std::lock_guard<std::mutex> lock(costmap_mutex_);
  if (!costmap_ || costmap_version_ != snapshot->version) {
    costmap_ =
        std::make_shared<Costmap>(std::shared_ptr<const OccupancyGrid>(snapshot, &snapshot->grid), costmap_options_);
    costmap_version_ = snapshot->version;
  }
  return costmap_;
}

std::shared_ptr<const Costmap> PlanningEngine::SceneCostmap(const std::shared_ptr<const Costmap>& map_costmap,
                                                            const PlanningScene& scene, bool draw_moving,
                                                            const Point2& start, const Point2& goal) const {
  // Nav2's obstacle layer, for one request: each body becomes an obstacle disc the inflation then
  // grows. A body over the start or the goal cannot be planned around now and is left out. Sensed
  // cells are left out only around the goal (the robot will see there when it gets near); around
  // the start the request's start recovery steps out of their inflation.
  OccupancyGrid grid = map_costmap->grid();
  const double keep_clear = map_costmap->options().inflation_radius + grid.resolution();
  bool drawn = false;
  for (const Point2& cell : scene.obstacle_cells) {
    if ((cell - goal).norm() < keep_clear || !grid.ContainsPoint(cell)) continue;
    grid.set(grid.CellOf(cell), OccupancyGrid::kOccupied);
    drawn = true;
  }
  for (const MovingBody& body : scene.moving) {
    if (!draw_moving) break;
    if ((body.position - start).norm() < body.radius + keep_clear ||
        (body.position - goal).norm() < body.radius + keep_clear) {
      continue;
    }
    grid.FillDisc(body.position, body.radius);
    drawn = true;
  }
  if (!drawn) return map_costmap;
  return std::make_shared<const Costmap>(std::make_shared<const OccupancyGrid>(std::move(grid)),
                                         map_costmap->options());
}

PathPlan PlanningEngine::ComputePath(const Point2& start, const Point2& goal, const std::string& planner_name,
                                     const std::map<std::string, double>& given, const StopRequested& stop,
                                     const PlanningScene& scene) {
  const auto t0 = std::chrono::steady_clock::now();
  CheckRequest(start, goal, scene);
  const GlobalPlanner& planner = Find(planner_name);
  const PlannerOptions options = ResolveOptions(planner, given);
  // Held for the whole request: `grid` refers into it even after a scene costmap replaces
  // `costmap`, and a concurrent LoadMap may drop the engine's own reference.
  const std::shared_ptr<const Costmap> map_costmap = CurrentCostmap();
  std::shared_ptr<const Costmap> costmap = map_costmap;
  const OccupancyGrid& grid = map_costmap->grid();
  CheckInsideMap(grid, start, "start");
  CheckInsideMap(grid, goal, "goal");
  const CellIndex goal_cell = GoalCell(*map_costmap, goal);
  CellIndex start_cell = StartCell(*map_costmap, start, options_.start_recovery_radius);

  const bool draw_moving = !scene.moving.empty() && !planner.plans_among_moving_bodies();
  if (draw_moving || !scene.obstacle_cells.empty()) {
    costmap = SceneCostmap(map_costmap, scene, draw_moving, grid.CellCenter(start_cell), goal);
    if (costmap->IsLethal(start_cell)) {
      // Beside a sensed obstacle: leave its inflation by the nearest way out, as from a wall's.
      const std::optional<CellIndex> free =
          costmap->NearestFree(start_cell, static_cast<int>(options_.start_recovery_radius / grid.resolution()), false);
      if (!free) {
        char buf[128];
        std::snprintf(buf, sizeof buf, " is hemmed in by obstacles the sensors found: no free cell within %.2f m",
                      options_.start_recovery_radius);
        throw Error(ErrorCode::kNotFound, "start " + FormatPoint(start) + buf);
      }
      start_cell = *free;
    }
  }
  const CellPath cells = planner.PlanInScene(*costmap, start_cell, goal_cell, options, scene, stop);
  if (cells.cells.empty()) {
    throw Error(ErrorCode::kNotFound, "no path from start " + FormatPoint(start) + " to goal " + FormatPoint(goal));
  }
  PathPlan plan;
  plan.planner = planner.name();
  plan.expansions = cells.expansions;
  const bool recovered = start_cell != grid.CellOf(start);
  plan.points = PathPoints(*costmap, cells, start, goal, recovered, options, stop);
  if (!cells.speed_limits.empty()) {
    // Speeds belong to cells.points, which keep their shape: start and goal take their neighbours'.
    plan.speed_limits.push_back(cells.speed_limits.front());
    plan.speed_limits.insert(plan.speed_limits.end(), cells.speed_limits.begin(), cells.speed_limits.end());
    plan.speed_limits.push_back(cells.speed_limits.back());
  }
  plan.length = PathLength(plan.points);
  // Planning time is the search and its smoothing, comparable across planners; the profile after.
  plan.planning_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  AddVelocityProfile(plan);
  return plan;
}

PathPlan PlanningEngine::ComputePathThroughPoses(const Point2& start, const std::vector<Point2>& waypoints,
                                                 const std::string& planner,
                                                 const std::map<std::string, double>& options,
                                                 const StopRequested& stop) {
  if (waypoints.empty()) throw Error(ErrorCode::kInvalidArgument, "waypoints is empty");
  PathPlan total;
  Point2 from = start;
  for (size_t i = 0; i < waypoints.size(); ++i) {
    PathPlan leg;
    try {
      leg = ComputePath(from, waypoints[i], planner, options, stop);
    } catch (const Error& e) {
      // Leg i's "goal" is waypoints[i]; its "start" is the previous waypoint (or the start).
      std::string message = e.what();
      const std::string goal_name = "waypoints[" + std::to_string(i) + "]";
      const std::string start_name = i == 0 ? "start" : "waypoints[" + std::to_string(i - 1) + "]";
      if (message.rfind("goal", 0) == 0)
        message = goal_name + message.substr(4);
      else if (message.rfind("start", 0) == 0)
        message = start_name + message.substr(5);
      else if (e.code() == ErrorCode::kNotFound)
        message = "leg to " + goal_name + ": " + message;
      throw Error(e.code(), message);
    }
    total.points.insert(total.points.end(), leg.points.begin() + (i == 0 ? 0 : 1), leg.points.end());
    if (!leg.speed_limits.empty()) {
      total.speed_limits.insert(total.speed_limits.end(), leg.speed_limits.begin() + (i == 0 ? 0 : 1),
                                leg.speed_limits.end());
    }
    total.length += leg.length;
    total.planning_time += leg.planning_time;
    total.expansions += leg.expansions;
    total.planner = leg.planner;
    from = waypoints[i];
  }
  AddVelocityProfile(total);  // one run through every waypoint, at rest only at the last
  return total;
}

void PlanningEngine::AddVelocityProfile(PathPlan& plan) const {
  const VelocityProfile profile = TimeOptimalProfile(plan.points, options_.velocity);
  plan.speeds = SpeedsAtPathPoints(plan.points, profile);
  plan.times = TimesAtPathPoints(plan.points, profile);
  plan.duration = profile.duration;
}

}  // namespace navd::planning
