#pragma once
// Where navd's brain processes and state variables sit in a brain (seed 000's utility functions,
// UtilityBrainOptions): the processes navd runs, found by name, and the state variables it
// measures. A brain may leave out any process but navigation, and any state variable.
#include <cstddef>

#include "services/navigation/utility_decision_maker.h"

namespace navd::navigation {

struct BrainLayout {
  // Throws navd::Error(kInvalidArgument) when the brain lacks a 'navigation' motor behaviour, has
  // a process of the wrong kind or one navd does not run, or names a state variable navd does not
  // measure.
  static BrainLayout Of(const UtilityDecisionMaker& brain);

  // Process indices; -1 where the brain has no such process.
  size_t navigation = 0;
  long emergency_stop = -1, wake_up = -1, avoidance = -1;  // motor behaviours
  long localization = -1, detection = -1, memory = -1;     // cognitive processes
  // State variable indices; -1 where the brain does not use it.
  long z_contact = -1, z_stale = -1, z_lost = -1, z_danger = -1, z_map_building = -1;
};

}  // namespace navd::navigation
