#include "services/navigation/avoidance_behaviour.h"

#include <string>

namespace navd::navigation {

std::optional<MotorCommand> AvoidanceBehaviour::Act(const MotorInputs& in) {
  const std::optional<DetectedObstacle> nearest = nearest_frontal_();
  const bool waited_out = avoider_.done() && in.now - done_at_ > avoider_.options().wait_before_retry;
  if (!nearest && (avoider_.phase() == AvoidancePhase::kIdle || waited_out)) return std::nullopt;
  // A pressed rear bumper closes the way back, whatever the rear sensor says.
  const AvoidanceSensing sensing = in.sensing(in.contact && in.rear_contact_only ? 0.0 : in.rear_free);
  // A manoeuvre starts when the behaviour takes over, and again when the robot has stood still a
  // while after one and the obstacle is still in the way (it waits for the robot, say).
  if ((in.activated || waited_out || avoider_.phase() == AvoidancePhase::kIdle) && nearest)
    avoider_.Start(in.pose, nearest->position, sensing, in.now, in.contact);
  const bool was_done = avoider_.done();
  MotorCommand out;
  out.wheels = in.fresh ? avoider_.Step(in.pose, sensing, in.now) : WheelSpeeds{};
  // The behaviour keeps its own utility up while its manoeuvre runs (the seed's Gamma_5).
  if (!avoider_.done()) {
    out.gamma = gamma_;
  } else if (!was_done) {
    done_at_ = in.now;
  }
  out.state = NavigationState::kAvoiding;
  out.status = std::string("avoiding a moving obstacle: ") + AvoidancePhaseName(avoider_.phase()) + " (zone " +
               std::to_string(avoider_.zone()) + ")";
  return out;
}

}  // namespace navd::navigation
