#pragma once
// Nav2's speed filter: whichever motor behaviour drives (an evasive turn in a loading bay is no
// faster either), neither rim is faster than the speed zones allow where the robot is and just
// ahead (SpeedZones::LimitAt). Without a pose estimate the robot stands. Zones are set by gRPC
// threads while the control thread filters: thread-safe.
#include <mutex>

#include "services/navigation/command_filter.h"
#include "services/navigation/speed_zones.h"

namespace navd::navigation {

class SpeedZoneFilter : public CommandFilter {
 public:
  SpeedZoneFilter(double robot_radius, const SpeedZoneOptions& options) : radius_(robot_radius), options_(options) {}
  WheelSpeeds Filter(const WheelSpeeds& command, const CommandContext& context) override;

  void SetZones(SpeedZones zones);
  SpeedZones zones() const;
  // The limit of the last filtered command (m/s; 0 without a pose, infinity outside every zone).
  double last_limit() const { return last_limit_; }

 private:
  double radius_;  // m
  SpeedZoneOptions options_;
  mutable std::mutex mutex_;
  SpeedZones zones_;  // guarded by mutex_
  double last_limit_ = 0.0;
};

}  // namespace navd::navigation
