#pragma once
// Book chapter 7's crowd control, the motor behaviour that drives a leg among people: while the
// navigator drives a leg (and more than handover_distance of it remains), the crowd controller's
// RRT in a model-predictive loop steers along the leg's path round the tracked people, and the
// path follower only keeps the robot's place on the path. It hands the robot back to the path
// follower near the goal, when paused, or when the path ahead lies behind the robot.
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "services/navigation/crowd_controller.h"
#include "services/navigation/navigator.h"
#include "services/navigation/person_tracker.h"
#include "services/planning/planning_engine.h"

namespace navd::navigation {

class CrowdSteering {
 public:
  // `person_radius`: m, each person's disc in the plans.
  CrowdSteering(const CrowdControllerOptions& options, double person_radius)
      : options_(options), person_radius_(person_radius), crowd_(options) {}

  // The crowd controller's command for a robot at `pose` (map frame) at `now` on the costmap
  // `planning` serves, or nullopt when it does not steer. `last`: the robot's last command (the controller starts from
  // it when it takes over); `people`: the people tracked now (map frame), asked only when it steers.
  std::optional<WheelSpeeds> Steer(Navigator& navigator, planning::PlanningEngine& planning, const Pose2& pose,
                                   const WheelSpeeds& last, const std::function<std::vector<TrackedPerson>()>& people,
                                   double now);

  const CrowdController& controller() const { return crowd_; }
  bool steering() const { return steering_; }  // it drove the last step

 private:
  std::optional<WheelSpeeds> HandBack(Navigator& navigator);

  CrowdControllerOptions options_;
  double person_radius_;
  CrowdController crowd_;
  bool steering_ = false;
};

}  // namespace navd::navigation
