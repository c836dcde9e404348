#pragma once
// What clients ask of navd's navigation (a goal, waypoints, deliveries), checked field by field
// and turned into the navigator's missions. Map frame, metres, radians.
#include <cstdint>
#include <string>
#include <vector>

#include "services/navigation/delivery_scheduler.h"
#include "services/navigation/navigator.h"
#include "services/planning/planning_engine.h"

namespace navd::navigation {

struct NavigateRequest {
  Pose2 goal;
  bool use_goal_heading = false;
  std::string planner;
  bool preempt = false;
};

struct MissionRequest {
  std::vector<Pose2> waypoints;  // map frame; headings used only with use_goal_heading
  bool use_goal_heading = false;
  bool cyclic = false;
  uint32_t laps = 0;          // with cyclic: 0 = until cancelled
  double max_distance = 0.0;  // m, 0 = no limit
  std::string planner;
  bool preempt = false;
};

// A delivery mission: navd orders the tasks' stops (ScheduleDeliveries) and drives them as a
// waypoint mission.
struct DeliveryRequest {
  std::vector<DeliveryTask> tasks;
  DeliveryScheduleOptions options;
  std::string planner;
  bool preempt = false;
};
inline constexpr size_t kMaxDeliveryTasks = 25;

// The mission of one goal; throws navd::Error(kInvalidArgument) naming `goal.theta` when it is
// used and not finite.
Mission MissionOf(const NavigateRequest& request);
// The mission of a waypoint list; errors name `waypoints`, `waypoints[i].theta`, `laps` or
// `max_distance`.
Mission MissionOf(const MissionRequest& request);
// Checks the number of tasks; errors name `tasks`.
void CheckDeliveryTasks(const DeliveryRequest& request);
// The order to drive the tasks' stops in from `start` (ScheduleDeliveries), with path lengths from
// `planning`; each stop is first checked from `start` (inside the map, free, reachable), and an
// error names it (`tasks[i].pickup`, `tasks[i].dropoff`).
DeliverySchedule PlanDeliverySchedule(planning::PlanningEngine& planning, const Point2& start,
                                      const DeliveryRequest& request, const planning::StopRequested& stop);
// The waypoint mission that drives `schedule`, back to `start` at the end with return_to_start.
MissionRequest WaypointsOf(const DeliverySchedule& schedule, const DeliveryRequest& request, const Point2& start);

}  // namespace navd::navigation
