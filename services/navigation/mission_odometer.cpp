#include "services/navigation/mission_odometer.h"

namespace navd::navigation {

void MissionOdometer::Start(const Pose2& pose, double now) {
  anchor_ = pose.translation();
  distance_ = 0.0;
  moving_time_ = 0.0;
  last_step_ = now;
}

void MissionOdometer::Step(const Pose2& pose, double now, bool moving, bool counting) {
  if (counting) {
    const double step = Distance(pose.translation(), anchor_);
    if (step >= kMaxStep) {
      anchor_ = pose.translation();
    } else if (step >= kChord) {
      distance_ += step;
      anchor_ = pose.translation();
    }
    if (moving && last_step_ >= 0.0 && now > last_step_) moving_time_ += now - last_step_;
  } else {
    anchor_ = pose.translation();
  }
  last_step_ = now;
}

}  // namespace navd::navigation
