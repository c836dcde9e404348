#pragma once
// How far a robot can drive before it meets something, and how fast it may drive towards it: the
// approach model of Nav2's collision monitor. Points in the robot frame (x ahead), metres, m/s.
#include <functional>
#include <vector>

#include "services/common/diff_drive.h"
#include "services/common/pose2.h"

namespace navd::navigation {

// Free distance (m, at most 4) from the rim of a robot of `radius` along a bearing (rad, robot
// frame), in a corridor as wide as the robot and 3 cm either side, among `local` points.
std::function<double(double)> FreeAlong(std::vector<Point2> local, double radius);

// The command with its forward speed capped so that, braking at `deceleration` (m/s^2), the robot
// stops `margin` (m) short of the nearest of `local` straight ahead; turning scaled with it.
WheelSpeeds CapApproach(const WheelSpeeds& wheels, std::vector<Point2> local, double radius, double margin,
                        double deceleration);

}  // namespace navd::navigation
