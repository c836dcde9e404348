#pragma once
// Ties the navigator to its inputs: takes a goal, checks it, plans from the current pose estimate
// with the planning engine, and hands the path to the navigator; each control step feeds it the
// pose. The gRPC adapter and the control loop both talk to this class only.
#include <functional>
#include <string>

#include "services/common/clock.h"
#include "services/localization/localizer.h"
#include "services/navigation/navigator.h"
#include "services/planning/planning_engine.h"

namespace navd::navigation {

struct NavigateRequest {
  Pose2 goal;
  bool use_goal_heading = false;
  std::string planner;
  bool preempt = false;
};

class NavigationExecutive {
 public:
  NavigationExecutive(planning::PlanningEngine& planning, const localization::Localizer& localizer,
                      const Clock& clock, const NavigatorOptions& options);

  // Throws navd::Error: kInvalidArgument (non-finite goal, goal outside the map or blocked,
  // unknown planner), kFailedPrecondition (no pose yet, or a goal active without preempt),
  // kNotFound (no path). Returns the goal id.
  uint64_t Navigate(const NavigateRequest& request, const planning::StopRequested& stop = {});
  bool Cancel(uint64_t goal_id = 0) { return navigator_.Cancel(goal_id); }
  // One control step at daemon clock time `now` (seconds); returns the wheel command (m/s).
  WheelSpeeds Step(bool sensors_fresh, double now);

  const Navigator& navigator() const { return navigator_; }

 private:
  planning::PlanningEngine& planning_;
  const localization::Localizer& localizer_;
  const Clock& clock_;
  Navigator navigator_;
};

}  // namespace navd::navigation
