#include "services/navigation/wake_up.h"

namespace navd::navigation {

std::optional<MotorCommand> WakeUp::Act(const MotorInputs& /*in*/) {
  MotorCommand out;
  out.state = NavigationState::kEmergencyStop;
  out.status =
      watch_.searching_nearby() ? "localization lost: searching nearby" : "localization lost: searching the map";
  const double v = watch_.options().search_turn_rate * wheel_base_ / 2.0;
  out.wheels = {-v, v};
  return out;
}

}  // namespace navd::navigation
