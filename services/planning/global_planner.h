#pragma once
// The plug-in interface of global planners (Nav2's GlobalPlanner, OMPL's Planner): a planner
// searches a costmap between two free cells and returns a cell path. Validation, start recovery,
// smoothing and timing live in PlanningEngine, so every planner gets them alike.
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "services/common/error.h"
#include "services/planning/costmap.h"

namespace navd::planning {

struct PlannerOptionSpec {
  std::string name;
  double default_value = 0.0;
  std::string description;
};

// Option values by name, already checked against the planner's specs and filled with defaults.
using PlannerOptions = std::map<std::string, double>;

// Polled during search; returns true when the caller's deadline passed or it cancelled.
using StopRequested = std::function<bool()>;

// For search loops: counts an expansion and polls stop() on the first and every 1024th (cheap, and
// prompt); throws navd::Error(kDeadlineExceeded) with the count when it is true.
inline void CountExpansion(uint64_t& expansions, const StopRequested& stop) {
  if ((++expansions & 1023) == 1 && stop && stop()) {
    throw Error(ErrorCode::kDeadlineExceeded,
                "planning stopped after " + std::to_string(expansions) + " expansions: deadline exceeded or cancelled");
  }
}

struct CellPath {
  std::vector<CellIndex> cells;  // start first, goal last; empty when no path exists
  // Continuous planners (OMPL) also give exact map-frame points, which replace the cells' centres.
  std::vector<Point2> points;
  // The points' shape matters (Dubins/Reeds-Shepp curves, a smooth gradient path with speeds):
  // no shortcutting afterwards.
  bool keep_shape = false;
  // Per point of `points`: the planner's speed limit as a fraction of the robot's top speed.
  std::vector<double> speed_limits;
  uint64_t expansions = 0;  // search nodes expanded, or roadmap/tree vertices
};

// A body that moves through the map, as the robot's perception reports it now: map frame, metres,
// m/s. Planners that plan around moving things predict it at constant velocity; the others ignore it.
struct MovingBody {
  Point2 position = Point2::Zero();
  Point2 velocity = Point2::Zero();
  double radius = 0.25;  // metres
  bool person = false;   // a person (book ch. 7's comfort zones) or an obstacle (seed 000's circle)
};

// What a request knows beyond the map.
struct PlanningScene {
  std::vector<MovingBody> moving;
  // Cells sensors found occupied that the map lacks (a 3-D obstacle layer's: a table top, a low
  // box), map frame: drawn into the costmap for every planner, inflated like walls.
  std::vector<Point2> obstacle_cells;
};

class GlobalPlanner {
 public:
  virtual ~GlobalPlanner() = default;
  virtual std::string name() const = 0;
  virtual std::string description() const = 0;
  virtual std::vector<PlannerOptionSpec> options() const = 0;
  // What the planner minimises, so benchmarks judge it fairly: the 8-connected grid length
  // (must match MovingAI optima), an any-angle length (must not exceed them), or a cost that
  // trades length for clearance (not judged on length).
  enum class Objective { kGridLength, kAnyAngleLength, kCost };
  virtual Objective objective() const { return Objective::kGridLength; }
  // Sampling planners that spend a time budget per query; batch runs skip them unless named.
  virtual bool time_budgeted() const { return false; }
  // start and goal are free cells of the costmap. Throws navd::Error(kDeadlineExceeded) when
  // stop() turns true.
  virtual CellPath Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                        const PlannerOptions& options, const StopRequested& stop) const = 0;
  // Whether PlanInScene plans around the scene's moving bodies itself; for the others the engine
  // draws the bodies into the costmap as obstacles.
  virtual bool plans_among_moving_bodies() const { return false; }
  // The same among the scene's moving bodies; planners that take them into account override it.
  virtual CellPath PlanInScene(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                               const PlannerOptions& options, const PlanningScene& /*scene*/,
                               const StopRequested& stop) const {
    return Plan(costmap, start, goal, options, stop);
  }
};

}  // namespace navd::planning
