#pragma once
// Odometry that jumps (the odom frame reset by a driver restart, a firmware glitch, a wrapped
// counter) would carry every estimate across the map in one step. A reading that implies more
// motion since the last than the robot can make is re-based: the jump counts as no motion and
// later readings continue from where the robot was. Odom frame; metres, radians, seconds.
#include "services/localization/localizer.h"

namespace navd::localization {

struct OdometryJumpLimits {
  double max_speed = 3.0;      // m/s no indoor robot exceeds
  double max_turn_rate = 8.0;  // rad/s
  double min_distance = 0.25;  // m: smaller steps are never jumps (jitter in the stamps)
  double min_angle = 0.5;      // rad
};

class OdometryJumpFilter {
 public:
  explicit OdometryJumpFilter(const OdometryJumpLimits& limits = {}) : limits_(limits) {}
  // The reading with any jump taken out; sets *jumped when this one was a jump.
  OdometryReading Filter(const OdometryReading& reading, bool* jumped = nullptr);
  int jumps() const { return jumps_; }

 private:
  OdometryJumpLimits limits_;
  bool have_last_ = false;
  OdometryReading last_raw_;
  Pose2 offset_;  // filtered = offset_ * raw
  int jumps_ = 0;
};

}  // namespace navd::localization
