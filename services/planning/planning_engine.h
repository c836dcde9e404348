#pragma once
// The planning front end shared by the gRPC adapter and the navigator: keeps the costmap in step
// with the current map, checks queries (finite, inside the map, not in an obstacle), moves a start
// that sits in the inflation zone to the nearest free cell, runs the named planner, and shortens
// the result by line-of-sight shortcuts. Points in metres, map frame.
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "services/common/map_store.h"
#include "services/planning/costmap.h"
#include "services/planning/global_planner.h"
#include "services/planning/velocity_profile.h"

namespace navd::planning {

struct PlanningEngineOptions {
  CostmapOptions costmap;
  std::string default_planner = "astar";
  // A start inside the inflation zone (robot close to a wall) is moved to the nearest free cell
  // within this distance, as Nav2 does; farther means the robot is in collision.
  double start_recovery_radius = 0.5;
  // The robot's limits for the velocity profile every plan carries.
  VelocityLimits velocity;
};

struct PathPlan {
  std::vector<Point2> points;        // start first, goal last
  std::vector<double> speed_limits;  // per point, fraction of top speed; empty unless the planner gives them
  // The time-optimal velocity profile along the path (book ch. 9), at each point: m/s (0 at the
  // goal) and seconds from the start; its total time.
  std::vector<double> speeds;
  std::vector<double> times;
  double duration = 0.0;
  double length = 0.0;         // metres
  double planning_time = 0.0;  // wall seconds
  uint64_t expansions = 0;
  std::string planner;
};

struct PlannerInfo {
  std::string name;
  std::string description;
  std::vector<PlannerOptionSpec> options;
  bool is_default = false;
  GlobalPlanner::Objective objective = GlobalPlanner::Objective::kGridLength;
  bool time_budgeted = false;
};

class PlanningEngine {
 public:
  PlanningEngine(const MapStore& maps, PlanningEngineOptions options);

  void Register(std::unique_ptr<GlobalPlanner> planner);
  std::vector<PlannerInfo> Planners() const;
  // False when the named planner (the default for "") spends a time budget per request, so a
  // caller may want it off a thread that serves others; true otherwise, unknown names included
  // (ComputePath rejects those at once).
  bool PlansBriefly(const std::string& planner) const;
  const PlanningEngineOptions& options() const { return options_; }
  const MapStore& maps() const { return maps_; }

  // Throws navd::Error: kInvalidArgument for non-finite, out-of-map or blocked points and unknown
  // planners or options (the message names the field), kNotFound when no path exists,
  // kFailedPrecondition when no map is loaded, kDeadlineExceeded when stop() turns true.
  // `scene`: moving bodies (checked: finite, radius >= 0). Planners that plan around them
  // (plans_among_moving_bodies) get them; for the others they are obstacles where they are now,
  // except one over the start or the goal.
  PathPlan ComputePath(const Point2& start, const Point2& goal, const std::string& planner,
                       const std::map<std::string, double>& options, const StopRequested& stop = {},
                       const PlanningScene& scene = {});

  // Plans start -> waypoints[0] -> ... as one path (legs joined, shared points once). Errors are
  // those of ComputePath with the field renamed to the waypoint (`waypoints[2]`).
  PathPlan ComputePathThroughPoses(const Point2& start, const std::vector<Point2>& waypoints,
                                   const std::string& planner, const std::map<std::string, double>& options,
                                   const StopRequested& stop = {});

  // The costmap of the current map (built on first use after a map change).
  std::shared_ptr<const Costmap> CurrentCostmap();
  // Changes the costmap's inflation radius (metres) for the requests that follow, e.g. a wider
  // margin while the map is still being built. Throws navd::Error(kInvalidArgument) when negative.
  void SetInflationRadius(double radius);
  double inflation_radius() const;

 private:
  const GlobalPlanner& Find(const std::string& name) const;
  // The costmap with the scene's obstacle cells drawn in, and its moving bodies unless the
  // planner plans among them itself.
  std::shared_ptr<const Costmap> SceneCostmap(const std::shared_ptr<const Costmap>& map_costmap,
                                              const PlanningScene& scene, bool draw_moving, const Point2& start,
                                              const Point2& goal) const;
  void AddVelocityProfile(PathPlan& plan) const;
  PlannerOptions ResolveOptions(const GlobalPlanner& planner, const std::map<std::string, double>& given) const;

  const MapStore& maps_;
  PlanningEngineOptions options_;
  std::vector<std::unique_ptr<GlobalPlanner>> planners_;
  mutable std::mutex costmap_mutex_;
  CostmapOptions costmap_options_;  // options_.costmap, until SetInflationRadius
  std::shared_ptr<const Costmap> costmap_;
  uint64_t costmap_version_ = 0;
};

// Length of a polyline, metres.
double PathLength(const std::vector<Point2>& points);

// Greedy line-of-sight shortcutting: from each kept point, follow the path while the straight
// segment from that point stays free on the costmap. Throws kDeadlineExceeded when stop() turns true.
std::vector<Point2> ShortcutPath(const Costmap& costmap, const std::vector<Point2>& points,
                                 const StopRequested& stop = {});

}  // namespace navd::planning
