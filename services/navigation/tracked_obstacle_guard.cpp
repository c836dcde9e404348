#include "services/navigation/tracked_obstacle_guard.h"

#include "services/navigation/free_way.h"

namespace navd::navigation {

WheelSpeeds TrackedObstacleGuard::Filter(const WheelSpeeds& wheels, const CommandContext& context) {
  if (context.source != CommandSource::kNavigation || !context.tracking_obstacles || context.among_people)
    return wheels;
  if (0.5 * (wheels.left + wheels.right) <= 0.0) return wheels;
  return CapApproach(wheels, context.moving_rims(), options_.robot_radius, options_.margin, options_.deceleration);
}

}  // namespace navd::navigation
