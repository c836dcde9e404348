#include "services/navigation/mission_time_left.h"

#include <algorithm>

namespace navd::navigation {

double MissionTimeLeft(const Mission& mission, const NavigationFeedback& f, double moving_time, double v_nav) {
  const auto& w = mission.waypoints;
  const auto leg = [&](size_t j) { return Distance(w[j - 1].pose.translation(), w[j].pose.translation()); };
  double rest = f.distance_remaining;
  for (size_t j = f.mission_index + 1; j < w.size(); ++j) rest += leg(j);
  if (mission.cyclic && mission.laps > 0 && f.laps_completed + 1 < mission.laps) {
    double lap = Distance(w.back().pose.translation(), w.front().pose.translation());
    for (size_t j = 1; j < w.size(); ++j) lap += leg(j);
    rest += lap * (mission.laps - f.laps_completed - 1);
  }
  if (mission.max_distance > 0.0) {
    const double left = std::max(0.0, mission.max_distance - f.distance_travelled);
    rest = mission.cyclic && mission.laps == 0 ? left : std::min(rest, left);
  }
  const double speed = moving_time > 5.0 ? std::max(0.05, f.distance_travelled / moving_time) : 0.6 * v_nav;
  return rest / speed;
}

}  // namespace navd::navigation
