#pragma once
// Seed 000's moving-obstacle detection (section 4.4) as a cognitive process: each scan, compared
// with the served map, updates the tracked obstacles and the danger level the avoidance behaviour
// and the command guards read. Detections made from a wrong pose are in the wrong place, so it
// forgets them while the pose is lost or the process is switched off. Written by the control
// thread, read by gRPC and telemetry threads: thread-safe. Map frame.
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "services/navigation/moving_obstacle_detector.h"

namespace navd::navigation {

class MovingObstacleDetection {
 public:
  explicit MovingObstacleDetection(const MovingObstacleDetectorOptions& options) : detector_(options) {}

  // One scan taken at `pose`, against `map` (the served map's caster; a new one resets the tracks).
  void Update(const localization::ScanReading& scan, const Pose2& pose, double now,
              std::shared_ptr<const RayCaster> map);
  void Reset();

  std::vector<DetectedObstacle> candidates() const;
  std::vector<DetectedObstacle> confirmed() const;
  std::optional<DetectedObstacle> nearest_frontal() const;
  double danger() const;

 private:
  mutable std::mutex mutex_;
  MovingObstacleDetector detector_;
  std::shared_ptr<const RayCaster> map_;
};

}  // namespace navd::navigation
