#pragma once
// What the motor behaviours that manoeuvre (the avoidance, the bumper recoil, the recoveries) see
// round the robot: the free way along any bearing among what the sensors show and where the
// tracked obstacles will be within a second, and the room behind, where the laser is blind.
#include <vector>

#include "services/common/occupancy_grid.h"
#include "services/common/pose2.h"
#include "services/navigation/moving_obstacle_avoidance.h"
#include "services/navigation/moving_obstacle_detector.h"

namespace navd::navigation {

// Eight points on the rim of obstacle `o` at each of `ahead` seconds on at its velocity, in the
// frame of a robot at `pose`, appended to `out`.
void AddPredictedRim(const DetectedObstacle& o, const Pose2& pose, std::initializer_list<double> ahead,
                     std::vector<Point2>& out);

// For a robot of `radius` (m) at `pose` (map frame): `local`, the sensors' returns in its frame;
// `map`, the served map (null: none); `rear_free` (m), the rear range sensor's reading; the
// detection's candidates (which close the way back for a second after the laser lost them) and
// confirmed obstacles (whose predicted rims close the ways ahead).
AvoidanceSensing SenseSurroundings(const Pose2& pose, double radius, std::vector<Point2> local,
                                   const OccupancyGrid* map, double rear_free,
                                   const std::vector<DetectedObstacle>& candidates,
                                   const std::vector<DetectedObstacle>& confirmed);

}  // namespace navd::navigation
