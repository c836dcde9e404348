#include "services/navigation/navigation_executive.h"

#include <cmath>

#include "services/common/error.h"

namespace navd::navigation {

NavigationExecutive::NavigationExecutive(planning::PlanningEngine& planning, const localization::Localizer& localizer,
                                         const Clock& clock, const NavigatorOptions& options)
    : planning_(planning), localizer_(localizer), clock_(clock), navigator_(options) {}

uint64_t NavigationExecutive::Navigate(const NavigateRequest& r, const planning::StopRequested& stop) {
  if (r.use_goal_heading && !std::isfinite(r.goal.theta)) {
    throw Error(ErrorCode::kInvalidArgument, "goal.theta is not a finite number");
  }
  const localization::PoseEstimate estimate = localizer_.Estimate();
  if (!estimate.valid) {
    throw Error(ErrorCode::kFailedPrecondition, "no pose estimate yet: navd has not received odometry");
  }
  // Validates the goal (finite, inside the map, free) and fails early when no path exists.
  const planning::PathPlan plan =
      planning_.ComputePath(estimate.pose.translation(), r.goal.translation(), r.planner, {}, stop);
  NavigationGoal goal{r.goal, r.use_goal_heading};
  if (!r.use_goal_heading) goal.pose.theta = 0.0;
  return navigator_.Start(goal, plan.points, plan.length, clock_.Now(), r.preempt);
}

WheelSpeeds NavigationExecutive::Step(bool sensors_fresh, double now) {
  const localization::PoseEstimate estimate = localizer_.Estimate();
  return navigator_.Step(estimate.pose, now, sensors_fresh && estimate.valid);
}

}  // namespace navd::navigation
