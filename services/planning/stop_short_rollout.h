#pragma once
// People as they are near a robot: someone who walks up to it stops short (people step round what
// blocks them; navsim's walkers stand until their way is free), so what touches is the robot's own
// motion into someone. A rollout drives the robot forward with each person walking on at their
// velocity until their next step would touch the robot, and standing there. The crowd RRT's
// escape judges its manoeuvres by it. Map frame, metres, radians, seconds.
#include <functional>
#include <limits>
#include <vector>

#include "services/planning/global_planner.h"
#include "services/planning/unicycle_model.h"

namespace navd::planning {

struct StopShortOptions {
  double robot_radius = 0.3;  // m
  double touch = 0.05;        // m: motion of the robot that brings its rim this near someone touches them
  double step = 0.05;         // s: the rollout's integration step
  // s after the start: the room is measured up to then, touches all the way (an escape's room is
  // judged while it is driven; the braking after it only has to stop short of everyone).
  double room_until = std::numeric_limits<double>::infinity();
};

struct StopShortRollout {
  std::vector<UnicycleState> states;  // the start, then one per step
  // s (the states' clock): when the robot's own motion first touched someone or left `allowed`;
  // infinity if it never did.
  double touch = std::numeric_limits<double>::infinity();
  // m: the least gap between the robot's rim and anyone's over the rollout up to room_until (as the
  // people walked and stood); minus infinity if the robot left `allowed` at any time (walls are
  // known exactly: leaving the map's allowed part is worse than any room).
  double room = std::numeric_limits<double>::infinity();
};

// Drives `start` for `duration` seconds with the input `input(state)` gives at each step.
// `allowed`, if given, says where the robot may be as far as the map goes.
StopShortRollout RollOutStopShort(const UnicycleState& start,
                                  const std::function<UnicycleInput(const UnicycleState&)>& input, double duration,
                                  const std::vector<MovingBody>& people, const UnicycleLimits& limits,
                                  const StopShortOptions& options,
                                  const std::function<bool(const Point2&)>& allowed = nullptr);

}  // namespace navd::planning
