#pragma once
// Speed limits by zone, as Nav2's speed filter: the robot drives through each zone of the world
// (SpeedZone) no faster than its max_speed, and brakes before it enters one so that it crosses
// the boundary at that speed already. Map frame, metres, m/s at the robot's rim.
#include <limits>
#include <vector>

#include "services/common/diff_drive.h"
#include "services/common/pose2.h"
#include "services/common/world.h"

namespace navd::navigation {

struct SpeedZoneOptions {
  double deceleration = 0.5;  // m/s^2: braking before a zone (the follower's final approach brakes at 0.6)
  double look_ahead = 0.6;    // m: from 0.5 m/s to 0.1 m/s takes 0.24 m at that
};

class SpeedZones {
 public:
  // Throws navd::Error(kInvalidArgument) naming `zones[i].<field>` for an unnamed or twice-named
  // zone, an area that is not a simple closed curve, or a max_speed that is not a positive number.
  explicit SpeedZones(std::vector<SpeedZone> zones = {});

  const std::vector<SpeedZone>& zones() const { return zones_; }

  // The fastest a robot of `radius` at `pose` may drive: the lowest max_speed of the zones its
  // disc touches, and of those on the look-ahead ahead of it along its heading, that much higher
  // as braking from there allows. Infinity without a zone.
  double LimitAt(const Pose2& pose, double radius, const SpeedZoneOptions& options) const;

  // The wheel speeds scaled so that neither rim is faster than `limit` (turning kept).
  static WheelSpeeds Cap(const WheelSpeeds& wheels, double limit);

 private:
  std::vector<SpeedZone> zones_;
};

}  // namespace navd::navigation
