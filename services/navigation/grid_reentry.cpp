#include "services/navigation/grid_reentry.h"

#include <cmath>

namespace navd::navigation {

const char* ReentryStateName(ReentryState state) {
  switch (state) {
    case ReentryState::kIdle: return "idle";
    case ReentryState::kCheckSector: return "checking the way ahead";
    case ReentryState::kRotate: return "turning to a clear way";
    case ReentryState::kForward: return "driving straight on";
  }
  return "?";
}

void GridReentry::Start(double now) {
  state_ = ReentryState::kCheckSector;
  started_at_ = now;
  turn_sign_ = 0.0;
  turned_ = 0.0;
  last_step_ = -1.0;
  any_clear_way_ = false;
}

bool GridReentry::SectorClear(const std::vector<Point2>& scan, double width, double radius) {
  for (const Point2& p : scan) {
    if (p.norm() <= radius && std::abs(std::atan2(p.y(), p.x())) <= width / 2.0) return false;
  }
  return true;
}

WheelSpeeds GridReentry::Step(const Pose2& pose, const std::vector<Point2>& scan, const std::optional<Point2>& toward,
                              double now) {
  if (!active()) return {};
  // Turning counts between consecutive steps only: another behaviour may have had the robot.
  if (last_step_ >= 0.0 && now - last_step_ <= kStepGap)
    turned_ += std::abs(NormalizeAngle(pose.theta - last_heading_));
  last_step_ = now;
  last_heading_ = pose.theta;
  if (any_clear_way_ && Distance(pose.translation(), relaxed_at_) > o_.relaxed_distance) {
    any_clear_way_ = false;  // driven far enough on any clear way: towards the grid again
    turned_ = 0.0;
  }
  if (!any_clear_way_ && turned_ > 2.0 * M_PI) {
    // A whole turn and no clear way towards the grid: any clear way will do for a while.
    any_clear_way_ = true;
    relaxed_at_ = pose.translation();
  }

  // State 3: is the way ahead clear, and (the addition) does it lead towards the grid? Driving
  // goes on while it stays clear and does not turn away from the grid.
  const std::optional<double> bearing =
      toward
          ? std::optional<double>(NormalizeAngle(std::atan2(toward->y() - pose.y, toward->x() - pose.x) - pose.theta))
          : std::nullopt;
  const double allowed = state_ == ReentryState::kForward ? M_PI / 2.0 : o_.max_bearing;
  const bool towards_grid = !bearing || any_clear_way_ || std::abs(*bearing) <= allowed;
  if (SectorClear(scan, o_.sector_width, o_.sector_radius) && towards_grid) {
    // State 5: equal wheel speeds, straight on.
    state_ = ReentryState::kForward;
    if (!any_clear_way_) turned_ = 0.0;
    turn_sign_ = 0.0;
    return {o_.forward_speed, o_.forward_speed};
  }
  // State 4: turn in place, the way the grid lies if it is known, and keep that way (turning
  // back and forth would look at the same blocked sector again and again).
  state_ = ReentryState::kRotate;
  if (turn_sign_ == 0.0) turn_sign_ = bearing && *bearing < 0.0 ? -1.0 : 1.0;
  return {-turn_sign_ * o_.rotate_speed, turn_sign_ * o_.rotate_speed};
}

}  // namespace navd::navigation
