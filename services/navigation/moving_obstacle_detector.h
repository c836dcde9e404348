#pragma once
// Moving-obstacle detection (MOD), Wahde et al. (seed 000, section 4.4). Each laser scan is
// compared with the scan the map predicts at the robot's estimated pose; runs of consecutive beams
// that come back more than T_mo short of the prediction are something the map does not hold.
// From the first and last beam of a run the detector infers a disc (position and radius), drops
// it when it is too far or too small, enlarges it by a margin and caps its radius, and keeps it as
// a candidate with a probability: p0 when new, p <- min(alpha p, 1) when seen again (within
// delta_max of where it was), p <- beta p when missed, forgotten below p_min. A candidate seen for
// at least dt_confirm seconds is a moving obstacle. The detector also keeps the danger level mu of
// the most threatening obstacle in the frontal half-plane, the state variable of the avoidance
// behaviour: mu <- (1 - alpha_mu) mu + alpha_mu m (m below). Map frame, metres, radians, seconds.
#include <memory>
#include <optional>
#include <vector>

#include "services/common/pose2.h"
#include "services/common/ray_caster.h"
#include "services/localization/localizer.h"

namespace navd::navigation {

struct MovingObstacleDetectorOptions {
  double threshold = 0.30;          // m, T_mo: a beam this much shorter than the map says is an obstacle
  double max_distance = 3.5;        // m, d_mo^max: candidates farther from the robot are dropped
  double min_radius = 0.04;         // m, r_mo^min: narrower runs are noise
  double margin = 0.5;              // the inferred radius is enlarged by 50 %
  double max_radius = 0.45;         // m, r_mo^max: larger (pose errors along a wall) is capped
  double associate_distance = 0.4;  // m, delta_mo^max: a candidate this close to a known one is that one
  double p0 = 0.4;
  double alpha = 1.5;  // > 1, on re-detection
  double beta = 0.6;   // < 1, on a miss
  double p_min = 0.2;
  double dt_confirm = 0.5;  // s, Delta T_mo
  int min_beams = 3;        // a run of fewer beams is a speck, not a body
  // Danger level. The seed leaves m's formula out ("based on the distance and angle"); ours is the
  // time to contact: each confirmed obstacle ahead is carried at its velocity, the robot at its
  // own, and m = 1 when their discs (the obstacle's enlarged, grown by contact_margin) would touch
  // within ttc_near seconds, 0 beyond ttc_far, linear between. Distance and angle both enter it,
  // and a body that crosses the robot's way counts before it is in front. As in the seed, m is 0
  // while the distance grows; also while it shrinks slower than closing_speed: an obstacle that
  // waits, next to a robot that waits, is no danger and must not hold both still for ever (the
  // plans route around it).
  double robot_radius = 0.20;    // m
  double contact_margin = 0.05;  // m
  // A robot at 0.5 m/s meeting a cart at 0.3 m/s closes 0.8 m/s: mu passes ~0.7 about three
  // scans after m does, and the robot needs ~0.3 s to stop.
  double ttc_near = 1.5;        // s
  double ttc_far = 3.0;         // s
  double danger_alpha = 0.4;    // alpha_mu in ]0, 1], per scan
  double closing_speed = 0.05;  // m/s
  // Obstacles slower than this (tracked velocity) add no danger: they stand, and plans avoid them.
  double min_obstacle_speed = 0.1;  // m/s
};

struct DetectedObstacle {
  Point2 position = Point2::Zero();  // map frame
  Point2 velocity = Point2::Zero();  // m/s, smoothed from successive detections
  double radius = 0.0;               // enlarged and capped
  double probability = 0.0;
  double first_seen = 0.0;  // s
  double last_seen = 0.0;   // s
  bool confirmed = false;   // seen for dt_confirm: an actual moving obstacle
};

class MovingObstacleDetector {
 public:
  explicit MovingObstacleDetector(const MovingObstacleDetectorOptions& options = {});

  // The static map the scans are compared with (its walls, as the localisers see them).
  void SetMap(std::shared_ptr<const RayCaster> map) { map_ = std::move(map); }
  // One MOD cycle: `scan` taken at `pose` (robot = laser frame, map frame) at time `now`.
  void Update(const localization::ScanReading& scan, const Pose2& pose, double now);
  // Forget everything (a relocalised robot's old detections are in the wrong place).
  void Reset();

  // Candidates and obstacles; confirmed() lists the obstacles only.
  const std::vector<DetectedObstacle>& candidates() const { return candidates_; }
  std::vector<DetectedObstacle> confirmed() const;
  // The most threatening confirmed obstacle in the frontal half-plane at the last update (the
  // highest m; the nearest when none threatens), if any.
  std::optional<DetectedObstacle> nearest_frontal() const { return nearest_; }
  double danger() const { return danger_; }
  const MovingObstacleDetectorOptions& options() const { return options_; }

  // The discs one scan shows (before association), for tests and tools.
  std::vector<DetectedObstacle> Segment(const localization::ScanReading& scan, const Pose2& pose) const;

 private:
  void UpdateDanger(const Pose2& pose, double now);

  MovingObstacleDetectorOptions options_;
  std::shared_ptr<const RayCaster> map_;
  std::vector<DetectedObstacle> candidates_;
  std::optional<DetectedObstacle> nearest_;
  std::optional<Pose2> last_pose_;          // the robot at the last update
  double last_update_ = 0.0;                // s
  Point2 robot_velocity_ = Point2::Zero();  // m/s, smoothed
  double danger_ = 0.0;
};

}  // namespace navd::navigation
