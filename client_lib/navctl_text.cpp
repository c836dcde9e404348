#include "client_lib/navctl_text.h"

namespace navd::navctl {

nlohmann::json PoseJson(const v1::Pose2D& p) { return {{"x", p.x()}, {"y", p.y()}, {"theta", p.theta()}}; }

const char* OutcomeText(v1::Outcome o) {
  switch (o) {
    case v1::SUCCEEDED: return "succeeded";
    case v1::FAILED: return "failed";
    case v1::CANCELED: return "canceled";
    case v1::PREEMPTED: return "preempted";
    default: return "unknown";
  }
}

const char* StateText(v1::NavigationState s) {
  switch (s) {
    case v1::IDLE: return "idle";
    case v1::ROTATING: return "rotating";
    case v1::DRIVING: return "driving";
    case v1::FINAL_ROTATION: return "final_rotation";
    case v1::STOPPED_STALE_SENSORS: return "stopped_stale_sensors";
    case v1::PAUSED: return "paused";
    case v1::EMERGENCY_STOP: return "emergency_stop";
    case v1::PLANNING: return "planning";
    case v1::AVOIDING: return "avoiding";
    case v1::RECOVERING: return "recovering";
    default: return "unknown";
  }
}

}  // namespace navd::navctl
