#include "services/navigation/brain_layout.h"

#include <string>
#include <utility>

#include "services/common/error.h"

namespace navd::navigation {
namespace {

const char* const kMeasured[] = {"contact", "sensors_stale", "localization_lost", "moving_obstacle_danger",
                                 "map_building"};
const char* const kProcesses[] = {"navigation",
                                  "emergency_stop",
                                  "wake_up",
                                  "localization",
                                  "moving_obstacle_detection",
                                  "moving_obstacle_avoidance",
                                  "long_term_memory"};

long StateIndexOr(const UtilityDecisionMaker& brain, const char* name) {
  const auto& vars = brain.options().state_variables;
  for (size_t k = 0; k < vars.size(); ++k)
    if (vars[k] == name) return static_cast<long>(k);
  return -1;
}

void CheckStateVariables(const UtilityDecisionMaker& brain) {
  for (const std::string& v : brain.options().state_variables) {
    bool known = false;
    for (const char* m : kMeasured) known = known || v == m;
    if (!known) {
      throw Error(ErrorCode::kInvalidArgument, "brain: state variable '" + v +
                                                   "' is not one navd measures (contact, sensors_stale, "
                                                   "localization_lost, moving_obstacle_danger, map_building)");
    }
  }
}

void CheckProcessNames(const UtilityDecisionMaker& brain) {
  for (const auto& p : brain.options().processes) {
    bool known = false;
    for (const char* k : kProcesses) known = known || p.name == k;
    if (!known) {
      throw Error(ErrorCode::kInvalidArgument, "brain: process '" + p.name +
                                                   "' is not one navd runs (navigation, emergency_stop, wake_up, "
                                                   "localization, moving_obstacle_detection, "
                                                   "moving_obstacle_avoidance, long_term_memory)");
    }
  }
}

}  // namespace

BrainLayout BrainLayout::Of(const UtilityDecisionMaker& brain) {
  const auto& processes = brain.options().processes;
  CheckStateVariables(brain);
  const long nav = brain.FindProcess("navigation");
  if (nav < 0 || processes[static_cast<size_t>(nav)].kind != ProcessKind::kMotor) {
    throw Error(ErrorCode::kInvalidArgument, "brain: a motor behaviour named 'navigation' is required");
  }
  BrainLayout l;
  l.navigation = static_cast<size_t>(nav);
  l.emergency_stop = brain.FindProcess("emergency_stop");
  l.wake_up = brain.FindProcess("wake_up");
  l.avoidance = brain.FindProcess("moving_obstacle_avoidance");
  l.localization = brain.FindProcess("localization");
  l.detection = brain.FindProcess("moving_obstacle_detection");
  l.memory = brain.FindProcess("long_term_memory");
  for (const auto& [name, index] : {std::pair<const char*, long>{"emergency_stop", l.emergency_stop},
                                    {"wake_up", l.wake_up},
                                    {"moving_obstacle_avoidance", l.avoidance}}) {
    if (index >= 0 && processes[static_cast<size_t>(index)].kind != ProcessKind::kMotor) {
      throw Error(ErrorCode::kInvalidArgument, std::string("brain: '") + name + "' must be a motor behaviour");
    }
  }
  for (const auto& [name, index] : {std::pair<const char*, long>{"localization", l.localization},
                                    {"moving_obstacle_detection", l.detection},
                                    {"long_term_memory", l.memory}}) {
    if (index >= 0 && processes[static_cast<size_t>(index)].kind != ProcessKind::kCognitive) {
      throw Error(ErrorCode::kInvalidArgument, std::string("brain: '") + name + "' must be a cognitive process");
    }
  }
  CheckProcessNames(brain);
  l.z_contact = StateIndexOr(brain, "contact");
  l.z_stale = StateIndexOr(brain, "sensors_stale");
  l.z_lost = StateIndexOr(brain, "localization_lost");
  l.z_danger = StateIndexOr(brain, "moving_obstacle_danger");
  l.z_map_building = StateIndexOr(brain, "map_building");
  return l;
}

}  // namespace navd::navigation
