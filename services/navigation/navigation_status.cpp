#include "services/navigation/navigation_status.h"

namespace navd::navigation {

void RecentResults::Add(uint64_t goal_id, const NavigationResult& result) {
  results_.emplace_back(goal_id, result);
  if (results_.size() > kKept) results_.erase(results_.begin());
}

std::optional<NavigationResult> RecentResults::Find(uint64_t goal_id) const {
  for (const auto& [id, r] : results_)
    if (id == goal_id) return r;
  return std::nullopt;
}

const char* NavigationStateName(NavigationState s) {
  switch (s) {
    case NavigationState::kIdle: return "idle";
    case NavigationState::kRotating: return "rotating";
    case NavigationState::kDriving: return "driving";
    case NavigationState::kFinalRotation: return "final_rotation";
    case NavigationState::kStoppedStaleSensors: return "stopped_stale_sensors";
    case NavigationState::kPaused: return "paused";
    case NavigationState::kEmergencyStop: return "emergency_stop";
    case NavigationState::kPlanning: return "planning";
    case NavigationState::kAvoiding: return "avoiding";
    case NavigationState::kRecovering: return "recovering";
  }
  return "unknown";
}

const char* OutcomeName(Outcome o) {
  switch (o) {
    case Outcome::kNone: return "none";
    case Outcome::kSucceeded: return "succeeded";
    case Outcome::kFailed: return "failed";
    case Outcome::kCanceled: return "canceled";
    case Outcome::kPreempted: return "preempted";
  }
  return "unknown";
}

}  // namespace navd::navigation
