#include "services/navigation/sonar_reflex.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "services/common/pose2.h"

namespace navd::navigation {

const char* SonarGroupName(SonarGroup group) {
  switch (group) {
    case SonarGroup::kLeft: return "LEFT";
    case SonarGroup::kFrontLeft: return "FRONT-LEFT";
    case SonarGroup::kFront: return "FRONT";
    case SonarGroup::kFrontRight: return "FRONT-RIGHT";
    case SonarGroup::kRight: return "RIGHT";
    case SonarGroup::kNone: break;
  }
  return "none";
}

SonarGroup SonarReflex::GroupOf(double angle) const {
  const double a = NormalizeAngle(angle);
  const double m = std::abs(a);
  if (m < o_.front_half) return SonarGroup::kFront;
  if (m < o_.diagonal_end) return a > 0 ? SonarGroup::kFrontLeft : SonarGroup::kFrontRight;
  if (m <= o_.side_end) return a > 0 ? SonarGroup::kLeft : SonarGroup::kRight;
  return SonarGroup::kNone;
}

ReflexResponse SonarReflex::Respond(const std::vector<SonarEcho>& stimuli, double navigator_bearing) const {
  ReflexResponse r;
  if (!o_.enabled) return r;
  // The nearest echo of each group is its intensity; FRONT keeps its left and right sensors apart.
  constexpr double kNone = std::numeric_limits<double>::infinity();
  double nearest = kNone, front_left = kNone, front_right = kNone;
  for (const SonarEcho& e : stimuli) {
    const SonarGroup g = GroupOf(e.angle);
    if (g == SonarGroup::kNone || !(e.range < o_.level_range[0])) continue;
    if (g == SonarGroup::kFront) {
      double& side = NormalizeAngle(e.angle) >= 0.0 ? front_left : front_right;
      side = std::min(side, e.range);
    }
    if (e.range < nearest) {
      nearest = e.range;
      r.group = g;
    }
  }
  if (r.group == SonarGroup::kNone) return r;
  r.range = nearest;
  r.level = nearest < o_.level_range[2] ? 3 : nearest < o_.level_range[1] ? 2 : 1;
  r.magnitude = o_.level_gain[r.level - 1];
  switch (r.group) {
    case SonarGroup::kLeft: r.orientation = o_.side_response; break;
    case SonarGroup::kRight: r.orientation = -o_.side_response; break;
    case SonarGroup::kFrontLeft: r.orientation = o_.diagonal_response; break;
    case SonarGroup::kFrontRight: r.orientation = -o_.diagonal_response; break;
    case SonarGroup::kFront: {
      // Away from the nearer of the two; on a tie, towards the subgoal's side.
      const bool obstacle_left = front_left != front_right ? front_left < front_right : navigator_bearing < 0.0;
      r.orientation = obstacle_left ? o_.front_response : -o_.front_response;
      break;
    }
    case SonarGroup::kNone: break;
  }
  return r;
}

WheelSpeeds SonarReflex::Blend(const WheelSpeeds& command, double navigator_bearing, const ReflexResponse& response,
                               double k_p, double max_wheel_speed) {
  const double v = 0.5 * (command.left + command.right);
  if (response.level == 0 || v <= 0.0) return command;
  const Point2 sum = Point2(std::cos(navigator_bearing), std::sin(navigator_bearing)) +
                     response.magnitude * Point2(std::cos(response.orientation), std::sin(response.orientation));
  const double heading = std::atan2(sum.y(), sum.x());
  const double forward = v * std::clamp(sum.x(), 0.0, 1.0);
  const double dv = k_p * v * heading;
  return ClampWheels({forward - dv, forward + dv}, max_wheel_speed);
}

}  // namespace navd::navigation
