#pragma once
// Seed 000's moving-obstacle avoidance (section 4.5) as a motor behaviour: when the danger of a
// moving obstacle ahead makes the utility functions pick it, the robot runs one evasive manoeuvre
// (MovingObstacleAvoidance: back up, turn away, pass), then stands; it starts another when the
// obstacle is still in the way after wait_before_retry. With nothing ahead to avoid (an obstacle
// beside or behind that is not going away) it leaves the robot to navigation, whose guards cap
// the speed near tracked obstacles: holding the robot there could stand it still for minutes.
#include <functional>
#include <optional>

#include "services/navigation/motor_behaviour.h"
#include "services/navigation/moving_obstacle_detector.h"

namespace navd::navigation {

class AvoidanceBehaviour : public MotorBehaviour {
 public:
  // `gamma`: the behaviour's own utility term while a manoeuvre runs (its process's
  // gamma_on_activation); `nearest_frontal`: the nearest confirmed obstacle ahead (map frame).
  AvoidanceBehaviour(const MovingObstacleAvoidanceOptions& options, double gamma,
                     std::function<std::optional<DetectedObstacle>()> nearest_frontal)
      : avoider_(options), gamma_(gamma), nearest_frontal_(std::move(nearest_frontal)) {}
  std::optional<MotorCommand> Act(const MotorInputs& in) override;
  void Release() override { avoider_.Stop(); }

 private:
  MovingObstacleAvoidance avoider_;
  double gamma_;
  std::function<std::optional<DetectedObstacle>()> nearest_frontal_;
  double done_at_ = -1.0;  // s: when the last manoeuvre ran its course
};

}  // namespace navd::navigation
