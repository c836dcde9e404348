#pragma once
// Seed 000's emergency stop (a motor behaviour): the robot stands while a bumper is pressed or its
// sensors are stale. What it touched goes into the plans (Nav2's bumper layer), and when the
// bumper lets go the robot first backs away from it a few centimetres (Nav2's back-up recovery):
// the leg replanned from against a wall starts by turning or driving along it, and pressed it
// again and again. When a bumper stays pressed (something pushed into the robot, from where the
// laser cannot see it, and both would wait forever) it creeps away from the pressed side after a
// while, when that way is free, until the contact ends.
#include <optional>

#include "services/navigation/motor_behaviour.h"

namespace navd::navigation {

struct EmergencyStopOptions {
  // Longer than an obstacle that gives up waits (the simulator's carts turn back after 4 s):
  // creeping away from one invites it to follow.
  double ease_off_after = 6.0;    // s
  double ease_off_speed = 0.05;   // m/s
  double recoil_distance = 0.10;  // m
  double recoil_speed = 0.10;     // m/s
  double robot_radius = 0.2;      // m
  double min_clearance = 0.10;    // m free the way it moves, to move at all
};

class EmergencyStop : public MotorBehaviour {
 public:
  // m: radius of what a bumper hit, as the plans see it; its size is unknown, so a disc as wide as
  // the front of the robot, just beyond its front rim.
  static constexpr double kContactDisc = 0.15;

  explicit EmergencyStop(const EmergencyStopOptions& options) : options_(options) {}
  std::optional<MotorCommand> Act(const MotorInputs& in) override;
  void Release() override;

 private:
  EmergencyStopOptions options_;
  double contact_since_ = -1.0;
  bool pressed_ = false;              // a bumper was pressed at the last step
  bool pressed_rear_ = false;         // ... the rear one only
  std::optional<Pose2> recoil_from_;  // backing away from a contact that ended, from here
  double recoil_until_ = 0.0;
};

}  // namespace navd::navigation
