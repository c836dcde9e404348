#pragma once
// Runs MovingAI scenarios through the planning engine and judges each path against the file's
// optimal octile length: grid planners must match it to the precision the file prints, any-angle
// planners must not exceed it, and cost-minimising planners must find a path. Used by `navctl plan --map --scen` and
// the correctness tests. Lengths in metres (MovingAI cells are 1 m); times in wall milliseconds.
#include <functional>
#include <string>
#include <vector>

#include "services/common/movingai_format.h"
#include "services/planning/planning_engine.h"

namespace navd::planning {

struct ScenarioMismatch {
  size_t index = 0;  // position in the scenario list
  double expected = 0.0;
  double actual = -1.0;  // -1 when no path was found
  std::string error;
};

struct ScenarioReport {
  std::string planner;
  GlobalPlanner::Objective objective = GlobalPlanner::Objective::kGridLength;
  size_t total = 0;
  size_t passed = 0;  // optimal (grid length), no longer than optimal (any-angle), or found (cost)
  double median_ms = 0.0;
  double p99_ms = 0.0;
  std::vector<ScenarioMismatch> mismatches;

  // "astar: 160/160 optimal, median 0.12 ms, p99 0.80 ms"
  std::string Summary() const;
};

// `engine` must plan on the scenarios' map. `progress(done, total)` is called after each one.
ScenarioReport RunScenarios(PlanningEngine& engine, const OccupancyGrid& grid,
                            const std::vector<MovingAiScenario>& scenarios, const std::string& planner,
                            const std::function<void(size_t, size_t)>& progress = {});

}  // namespace navd::planning
