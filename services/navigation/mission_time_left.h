#pragma once
// The navigator's ETA for an active mission.
#include "services/navigation/navigator.h"

namespace navd::navigation {

// Seconds left of `mission` at feedback `f`: the distance left (this leg's path, then straight
// lines through the remaining waypoints, to the mission's end, or to the lap's end when it repeats
// without end; no more than max_distance allows) at the mission's own average speed once it has
// driven `moving_time` > 5 s, before that at 0.6 of the cruise speed `v_nav` (m/s).
double MissionTimeLeft(const Mission& mission, const NavigationFeedback& f, double moving_time, double v_nav);

}  // namespace navd::navigation
