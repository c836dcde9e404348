#include "services/navigation/emergency_stop.h"

namespace navd::navigation {

std::optional<MotorCommand> EmergencyStop::Act(const MotorInputs& in) {
  MotorCommand out;
  out.state = NavigationState::kEmergencyStop;
  if (!in.contact) {
    contact_since_ = -1.0;
  } else if (contact_since_ < 0.0) {
    contact_since_ = in.now;
  }
  // A pressed rear bumper is something that drove into the robot. The planner leaves out bodies
  // this near the start, so the touched disc counts once a back-up has taken the robot away.
  if (in.contact && !pressed_ && !in.rear_contact_only)
    out.touched = MotorCommand::Touch{in.pose * Point2(options_.robot_radius + kContactDisc, 0.0), kContactDisc};
  if (in.contact) {
    out.gamma = 1.0;  // holds the behaviour past the release, for the recoil
    pressed_ = true;
    pressed_rear_ = in.rear_contact_only;
    recoil_from_.reset();
  } else if (pressed_) {
    pressed_ = false;
    recoil_from_ = in.pose;
    recoil_until_ = in.now + 2.0 * options_.recoil_distance / options_.recoil_speed + 1.0;
  }
  if (recoil_from_) {
    const AvoidanceSensing sensing = in.sensing(in.rear_free);
    const double way = pressed_rear_ ? sensing.free_along(0.0) : sensing.rear_free;
    if (Distance(in.pose.translation(), recoil_from_->translation()) < options_.recoil_distance &&
        in.now < recoil_until_ && way > options_.min_clearance) {
      out.gamma = 1.0;
      out.status = "bumper released: backing away";
      const double v = pressed_rear_ ? options_.recoil_speed : -options_.recoil_speed;
      out.wheels = {v, v};
      return out;
    }
    recoil_from_.reset();
    out.gamma = 0.0;
  }
  const bool ease_off = in.contact && in.now - contact_since_ >= options_.ease_off_after;
  out.status = !in.contact ? "emergency stop" : ease_off ? "bumper pressed: easing off" : "bumper pressed";
  if (ease_off) {
    const AvoidanceSensing sensing = in.sensing(in.rear_free);
    const double v = options_.ease_off_speed;
    if (in.rear_contact_only && sensing.free_along(0.0) > options_.min_clearance) {
      out.wheels = {v, v};
    } else if (!in.rear_contact_only && sensing.rear_free > options_.min_clearance) {
      out.wheels = {-v, -v};
    }
  }
  return out;
}

void EmergencyStop::Release() {
  pressed_ = false;  // no recoil pending
  recoil_from_.reset();
}

}  // namespace navd::navigation
