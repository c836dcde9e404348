#include "services/navigation/crowd_steering.h"

#include <algorithm>
#include <cmath>

namespace navd::navigation {

std::optional<WheelSpeeds> CrowdSteering::HandBack(Navigator& navigator) {
  if (steering_) {
    steering_ = false;
    navigator.SetExternalSteering(false);
  }
  return std::nullopt;
}

std::optional<WheelSpeeds> CrowdSteering::Steer(Navigator& navigator, planning::PlanningEngine& planning,
                                                const Pose2& pose, const WheelSpeeds& last,
                                                const std::function<std::vector<TrackedPerson>()>& people, double now) {
  const NavigationStatus status = navigator.Status();
  const bool steer = status.active && !status.paused && status.feedback.state == NavigationState::kDriving &&
                     status.feedback.distance_remaining > options_.handover_distance;
  if (!steer) return HandBack(navigator);
  const double b = navigator.options().follower.wheel_base;
  std::vector<Point2> path = navigator.PathAhead(options_.lookahead);
  const std::shared_ptr<const planning::Costmap> costmap = planning.CurrentCostmap();
  // Facing further off than max_heading_error (by default never), the path follower turns the
  // robot round first; the crowd RRT turns it back from anything less.
  const bool facing =
      !path.empty() &&
      std::abs(NormalizeAngle(std::atan2(path.back().y() - pose.y, path.back().x() - pose.x) - pose.theta)) <=
          options_.max_heading_error;
  if (!facing || !costmap) return HandBack(navigator);
  if (!steering_) {
    // From what the robot was doing: the path follower's last command.
    crowd_.Reset(std::max(0.0, 0.5 * (last.left + last.right)), (last.right - last.left) / b);
    steering_ = true;
    navigator.SetExternalSteering(true);
  }
  std::vector<planning::MovingBody> bodies;
  for (const TrackedPerson& p : people()) bodies.push_back({p.position, p.velocity, person_radius_, true});
  const UnicycleCommand u = crowd_.Step(*costmap, pose, path, bodies, now);
  return WheelSpeeds{u.v - 0.5 * u.w * b, u.v + 0.5 * u.w * b};
}

}  // namespace navd::navigation
