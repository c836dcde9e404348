#pragma once
// Nav2's collision monitor, for what the map does not hold: while navigation drives, the robot
// never drives forward faster than it can stop in before a moving tracked obstacle (any candidate
// of the moving-obstacle detection, now or within the next second). The danger level reacts to
// what closes in; this catches what appears close, round a corner, and where it will be in a
// second (the scan guard stops short of where things are now). Off among people, where the crowd
// controller does the avoiding, and while the detection does not run.
#include "services/navigation/command_filter.h"

namespace navd::navigation {

struct TrackedObstacleGuardOptions {
  double robot_radius = 0.2;  // m
  double margin = 0.10;       // m short of the obstacle's predicted rim
  double deceleration = 0.7;  // m/s^2: a third of the seed robot's wheel limit, for the command's latency
};

class TrackedObstacleGuard : public CommandFilter {
 public:
  explicit TrackedObstacleGuard(const TrackedObstacleGuardOptions& options) : options_(options) {}
  WheelSpeeds Filter(const WheelSpeeds& command, const CommandContext& context) override;

 private:
  TrackedObstacleGuardOptions options_;
};

}  // namespace navd::navigation
