#include "services/navigation/moving_obstacle_detection.h"

namespace navd::navigation {

void MovingObstacleDetection::Update(const localization::ScanReading& scan, const Pose2& pose, double now,
                                     std::shared_ptr<const RayCaster> map) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!map) return;
  if (map != map_) {
    map_ = std::move(map);
    detector_.SetMap(map_);
    detector_.Reset();
  }
  detector_.Update(scan, pose, now);
}

void MovingObstacleDetection::Reset() {
  std::lock_guard<std::mutex> lock(mutex_);
  detector_.Reset();
}

std::vector<DetectedObstacle> MovingObstacleDetection::candidates() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return detector_.candidates();
}

std::vector<DetectedObstacle> MovingObstacleDetection::confirmed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return detector_.confirmed();
}

std::optional<DetectedObstacle> MovingObstacleDetection::nearest_frontal() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return detector_.nearest_frontal();
}

double MovingObstacleDetection::danger() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return detector_.danger();
}

}  // namespace navd::navigation
