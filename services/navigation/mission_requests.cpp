#include "services/navigation/mission_requests.h"

#include <cmath>
#include <limits>
#include <utility>

#include "services/common/error.h"

namespace navd::navigation {

Mission MissionOf(const NavigateRequest& r) {
  if (r.use_goal_heading && !std::isfinite(r.goal.theta)) {
    throw Error(ErrorCode::kInvalidArgument, "goal.theta is not a finite number");
  }
  NavigationGoal goal{r.goal, r.use_goal_heading};
  if (!r.use_goal_heading) goal.pose.theta = 0.0;
  return Mission{{goal}};
}

Mission MissionOf(const MissionRequest& r) {
  if (r.waypoints.empty()) throw Error(ErrorCode::kInvalidArgument, "waypoints: at least one is required");
  if (r.cyclic && r.waypoints.size() < 2) {
    throw Error(ErrorCode::kInvalidArgument, "waypoints: a cyclic mission needs at least two");
  }
  if (!r.cyclic && r.laps > 0) throw Error(ErrorCode::kInvalidArgument, "laps: only a cyclic mission has laps");
  if (!std::isfinite(r.max_distance) || r.max_distance < 0.0) {
    throw Error(ErrorCode::kInvalidArgument, "max_distance must be a non-negative number of metres");
  }
  Mission mission;
  mission.cyclic = r.cyclic;
  mission.laps = r.laps;
  mission.max_distance = r.max_distance;
  for (size_t i = 0; i < r.waypoints.size(); ++i) {
    if (r.use_goal_heading && !std::isfinite(r.waypoints[i].theta)) {
      throw Error(ErrorCode::kInvalidArgument, "waypoints[" + std::to_string(i) + "].theta is not a finite number");
    }
    NavigationGoal g{r.waypoints[i], r.use_goal_heading};
    if (!r.use_goal_heading) g.pose.theta = 0.0;
    mission.waypoints.push_back(g);
  }
  return mission;
}

void CheckDeliveryTasks(const DeliveryRequest& r) {
  if (r.tasks.empty()) throw Error(ErrorCode::kInvalidArgument, "tasks: at least one is required");
  if (r.tasks.size() > kMaxDeliveryTasks) {
    throw Error(ErrorCode::kInvalidArgument, "tasks: at most " + std::to_string(kMaxDeliveryTasks) + " in one mission");
  }
}

DeliverySchedule PlanDeliverySchedule(planning::PlanningEngine& planning, const Point2& start, const DeliveryRequest& r,
                                      const planning::StopRequested& stop) {
  // The scheduler asks for the lengths from the start again: they are kept.
  std::vector<std::pair<Point2, double>> from_start;
  for (size_t i = 0; i < r.tasks.size(); ++i) {
    for (const bool pickup : {true, false}) {
      const std::string field = "tasks[" + std::to_string(i) + "]." + (pickup ? "pickup" : "dropoff");
      const Point2& p = pickup ? r.tasks[i].pickup : r.tasks[i].dropoff;
      if (!p.allFinite()) throw Error(ErrorCode::kInvalidArgument, field + " is not a finite point");
      try {
        from_start.emplace_back(p, planning.ComputePath(start, p, r.planner, {}, stop).length);
      } catch (const Error& e) {
        throw Error(e.code(), field + ": " + e.what());
      }
    }
  }
  return ScheduleDeliveries(start, r.tasks, r.options, [&](const Point2& a, const Point2& b) {
    if (a == start) {
      for (const auto& [p, length] : from_start)
        if (p == b) return length;
    }
    try {
      return planning.ComputePath(a, b, r.planner, {}, stop).length;
    } catch (const Error&) {
      return std::numeric_limits<double>::infinity();
    }
  });
}

MissionRequest WaypointsOf(const DeliverySchedule& schedule, const DeliveryRequest& r, const Point2& start) {
  MissionRequest mission;
  for (const DeliveryStop& s : schedule.stops) mission.waypoints.emplace_back(s.at.x(), s.at.y(), 0.0);
  if (r.options.return_to_start) mission.waypoints.emplace_back(start.x(), start.y(), 0.0);
  mission.planner = r.planner;
  mission.preempt = r.preempt;
  return mission;
}

}  // namespace navd::navigation
