#pragma once
// Delivery missions: seed 004's task-scheduling layer ("prioritize tasks, and optimize schedule")
// over seed 000's delivery rounds. Each task is a pickup and a dropoff; the scheduler orders every
// stop so the round is as short as it can find, by the planner's path lengths between stops, under
// three rules: a task's pickup comes before its dropoff, the robot never carries more than
// `capacity` loads, and a task of higher priority is delivered before one of lower priority.
// Up to exact_up_to tasks the round is the shortest there is (dynamic programming over the sets
// of stops done: the load and the priority rule depend on the set alone). Beyond, cheapest
// feasible insertion of the tasks (highest priority first, from several task orders), each
// followed by local search (move a stop, move a task's pair, swap two stops) until no move
// shortens the round; the shortest wins. Map frame, metres.
#include <algorithm>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "services/common/pose2.h"

namespace navd::navigation {

struct DeliveryTask {
  std::string name;
  Point2 pickup = Point2::Zero();
  Point2 dropoff = Point2::Zero();
  int priority = 0;  // higher first
};

struct DeliveryScheduleOptions {
  size_t capacity = 0;           // loads on board at once; 0: no limit
  bool return_to_start = false;  // the round ends where the robot started
  size_t exact_up_to = 8;        // tasks; 2^(2n) x 2n states (8: 1 M, about 10 ms)
  int restarts = 8;              // extra insertion orders tried beyond it (seeded, repeatable)
};

struct DeliveryStop {
  size_t task = 0;  // index into the tasks
  bool pickup = true;
  Point2 at = Point2::Zero();
  double leg_length = 0.0;  // m from the stop before (the start for the first)
};

struct DeliverySchedule {
  std::vector<DeliveryStop> stops;
  double length = 0.0;              // m, the whole round (with the way back when asked)
  double given_order_length = 0.0;  // m, each task picked up and dropped off in the order given
};

// Path length in metres between two points; +infinity when there is no path. Taken as the same
// both ways (each pair is asked once).
using PathLength = std::function<double(const Point2&, const Point2&)>;

// Throws navd::Error(kInvalidArgument) naming tasks[i] for a bad task (non-finite points, a
// priority order the capacity cannot hold), kNotFound naming the stop no path reaches.
DeliverySchedule ScheduleDeliveries(const Point2& start, const std::vector<DeliveryTask>& tasks,
                                    const DeliveryScheduleOptions& options, const PathLength& length);

}  // namespace navd::navigation
