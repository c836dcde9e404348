#pragma once
// Seed 000's motor behaviours: the utility functions pick one each control step, and it alone
// drives the robot (its command then goes through the command filters). Navigation is the
// executive's own; the others are small classes behind this interface. Map frame, metres, m/s,
// seconds of the daemon's clock.
#include <functional>
#include <optional>
#include <string>

#include "services/common/diff_drive.h"
#include "services/common/pose2.h"
#include "services/navigation/moving_obstacle_avoidance.h"
#include "services/navigation/navigator.h"

namespace navd::navigation {

// What a motor behaviour knows of the step.
struct MotorInputs {
  Pose2 pose;                      // the pose estimate
  bool fresh = false;              // the sensors are fresh and the estimate valid
  bool contact = false;            // a bumper is pressed
  bool rear_contact_only = false;  // ... and it is the rear one only
  bool activated = false;          // the behaviour has just taken the robot
  double rear_free = 0.0;          // m free behind the rim by the rear range sensor
  double now = 0.0;                // s
  // What the robot sees round it (the laser, the map, tracked obstacles), with `rear_free` (m)
  // as the rear sensor's reading.
  std::function<AvoidanceSensing(double rear_free)> sensing;
};

// What a motor behaviour does this step.
struct MotorCommand {
  WheelSpeeds wheels;
  NavigationState state = NavigationState::kEmergencyStop;  // for the navigator's feedback
  std::string status;                                       // why, in words
  // The behaviour's own utility term (the seed's Gamma), when it sets it: a behaviour holds the
  // robot past what the state variables say while its manoeuvre runs.
  std::optional<double> gamma;
  // Something the robot touched, which the plans must go round: a disc, map frame, metres.
  struct Touch {
    Point2 at;
    double radius = 0.0;
  };
  std::optional<Touch> touched;
};

class MotorBehaviour {
 public:
  virtual ~MotorBehaviour() = default;
  // This step's command; nullopt when there is nothing for it to do, and navigation drives.
  virtual std::optional<MotorCommand> Act(const MotorInputs& in) = 0;
  // Another behaviour has the robot.
  virtual void Release() {}
};

}  // namespace navd::navigation
