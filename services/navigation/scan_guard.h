#pragma once
// Nav2's collision monitor (its approach model) on the laser: whatever the map says (one still
// being built, a wall a few centimetres off, a box it lacks), the robot never drives forward faster
// than it can stop in before what the last scan (and the 3-D layer) saw ahead. The plans keep the
// rim 0.1 m from walls, so on a planned path it binds only head-on. Nor does the robot turn with
// something at its rim ahead unless it backs away as it turns. Among people (who may stand
// behind, and whom the crowd controller's plans steer round) it neither backs nor turns where it
// stopped the robot. Guards the commands of navigation and of the drive back onto the grid.
#include "services/navigation/command_filter.h"

namespace navd::navigation {

struct ScanGuardOptions {
  double robot_radius = 0.2;  // m
  double margin = 0.05;       // m short of the nearest return ahead
  double deceleration = 0.7;  // m/s^2
  // Turning in place is never quite in place: each wheel misses its speed a little, so the centre
  // creeps along the heading. With something this near the rim in front, the robot keeps only the
  // straight part of its command; when that cannot go on either, it turns while backing at
  // backing, if the way back is free for backing_room.
  double turn_gap = 0.05;      // m
  double backing = 0.03;       // m/s
  double backing_room = 0.05;  // m
};

class ScanGuard : public CommandFilter {
 public:
  explicit ScanGuard(const ScanGuardOptions& options) : options_(options) {}
  WheelSpeeds Filter(const WheelSpeeds& command, const CommandContext& context) override;

 private:
  ScanGuardOptions options_;
};

}  // namespace navd::navigation
