#include "services/planning/stop_short_rollout.h"

namespace navd::planning {

StopShortRollout RollOutStopShort(const UnicycleState& start,
                                  const std::function<UnicycleInput(const UnicycleState&)>& input, double duration,
                                  const std::vector<MovingBody>& people, const UnicycleLimits& limits,
                                  const StopShortOptions& o, const std::function<bool(const Point2&)>& allowed) {
  StopShortRollout out;
  out.states.push_back(start);
  std::vector<Point2> at;
  at.reserve(people.size());
  for (const MovingBody& p : people) at.push_back(p.position);
  UnicycleState s = start;
  for (double t = o.step; t <= duration + 1e-9; t += o.step) {
    const Point2 from = s.position();
    s = Propagate(s, input(s), o.step, limits);
    if (allowed && !allowed(s.position())) {  // a wall's inflation: as bad as touching someone
      out.room = -std::numeric_limits<double>::infinity();
      out.touch = std::min(out.touch, s.t);
    }
    const bool moved = Distance(from, s.position()) > 1e-9;
    for (size_t i = 0; i < people.size(); ++i) {
      const double reach = people[i].radius + o.robot_radius;
      const double gap = Distance(s.position(), at[i]) - reach;
      // Nearer than before and within `touch`: the robot's own motion into them.
      if (moved && gap < o.touch && gap < Distance(from, at[i]) - reach - 1e-9) out.touch = std::min(out.touch, s.t);
      const Point2 next = at[i] + o.step * people[i].velocity;
      if (Distance(s.position(), next) - reach > 0.0) at[i] = next;  // else they stop short
      if (t <= o.room_until + 1e-9) out.room = std::min(out.room, Distance(s.position(), at[i]) - reach);
    }
    out.states.push_back(s);
  }
  return out;
}

}  // namespace navd::planning
