#pragma once
// Seed 000's wake-up behaviour: while the pose is lost the robot turns in place, whether or not a
// mission is active (an idle robot that stands still can never be found again), and the
// localisation watch searches for the pose. Turning shows the localiser the whole room; it cannot
// tell places apart standing still.
#include "services/navigation/localization_watch.h"
#include "services/navigation/motor_behaviour.h"

namespace navd::navigation {

class WakeUp : public MotorBehaviour {
 public:
  // `wheel_base`: m between the wheels.
  WakeUp(const LocalizationWatch& watch, double wheel_base) : watch_(watch), wheel_base_(wheel_base) {}
  std::optional<MotorCommand> Act(const MotorInputs& in) override;

 private:
  const LocalizationWatch& watch_;
  double wheel_base_;
};

}  // namespace navd::navigation
