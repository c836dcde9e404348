#pragma once
// The planners navd offers, registered in one place for the daemon, navctl's offline mode, the
// tests and the benchmarks.
#include "services/planning/planning_engine.h"

namespace navd::planning {

void RegisterDefaultPlanners(PlanningEngine& engine);

}  // namespace navd::planning
