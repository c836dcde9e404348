#include "services/navigation/scan_guard.h"

#include <algorithm>
#include <limits>

#include "services/navigation/free_way.h"

namespace navd::navigation {

WheelSpeeds ScanGuard::Filter(const WheelSpeeds& wheels, const CommandContext& context) {
  if (context.source == CommandSource::kOther) return wheels;
  constexpr double kCreeping = 0.01;  // m/s: slower forward is standing
  const bool manoeuvre = !context.among_people;
  const bool turning = wheels.left != wheels.right;
  if (!turning && wheels.left <= 0.0) return wheels;  // standing or backing straight: nothing to guard
  std::vector<Point2> local = context.returns();
  if (local.empty()) return wheels;
  const auto cap = [&](const WheelSpeeds& w, std::vector<Point2> points) {
    return CapApproach(w, std::move(points), options_.robot_radius, options_.margin, options_.deceleration);
  };
  // m from the rim to the nearest return in front: away from people, anywhere in the front half
  // (navigation turning towards a cart waiting 70 degrees off its heading swept its rim into it);
  // among people, within 60 degrees of the heading.
  const double rim = options_.robot_radius, front = manoeuvre ? 0.0 : 0.5;  // cos of the half-angle
  double gap = std::numeric_limits<double>::infinity();
  for (const Point2& p : local)
    if (p.x() > front * p.norm()) gap = std::min(gap, p.norm() - rim);
  if (turning && gap < options_.turn_gap) {
    // The straight part alone, if it can go on; a robot that can neither would stand there for
    // good (its rim beside a door jamb ahead, after every recovery), so it turns while backing
    // away instead, which no creep brings nearer.
    const double v = 0.5 * (wheels.left + wheels.right);
    const WheelSpeeds straight = v > 0.0 ? cap({v, v}, local) : WheelSpeeds{v, v};
    if (!manoeuvre || straight.left > kCreeping) return straight;
    if (context.rear_room() < options_.backing_room) return straight;
    const double back = std::min(v, -options_.backing), half_turn = 0.5 * (wheels.right - wheels.left);
    return {back - half_turn, back + half_turn};
  }
  if (0.5 * (wheels.left + wheels.right) <= 0.0) return wheels;
  const WheelSpeeds capped = cap(wheels, std::move(local));
  if (!turning || !manoeuvre || 0.5 * (capped.left + capped.right) > kCreeping) return capped;
  // Stopped short of what is ahead, with nothing at the rim in front of it (a cart waiting at its
  // side-front is touched by the creep of such a turn): it still turns as it was told. Scaled down
  // with the forward speed, the turn would stop too, and a robot whose heading grazes the wall
  // beside it would stand there until the recoveries.
  const double v = 0.5 * (capped.left + capped.right), half_turn = 0.5 * (wheels.right - wheels.left);
  return {v - half_turn, v + half_turn};
}

}  // namespace navd::navigation
