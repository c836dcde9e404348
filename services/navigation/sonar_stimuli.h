#pragma once
// Which sonar echoes seed 004's reflex answers: those the map and what the laser sees do not
// explain (a glass pane, a table top, a box under the laser's plane), within remember_within.
// Sonar mounting angles in the robot frame; map frame otherwise; metres, radians.
#include <vector>

#include "services/common/occupancy_grid.h"
#include "services/common/pose2.h"
#include "services/navigation/sonar_reflex.h"

namespace navd::navigation {

// The echoes of sensors on the rim of a robot of radius `rim` at `pose` nearer than both the map
// (`map`; null: none, as while it is being built) and the sensors' returns `local` (robot frame)
// say anything is along the sensor's cone, within the reflex's remember_within.
std::vector<SonarEcho> UnexplainedEchoes(const std::vector<SonarEcho>& echoes, const Pose2& pose, double rim,
                                         const std::vector<Point2>& local, const OccupancyGrid* map,
                                         const SonarReflex& reflex);

// Metres from `origin` to the nearest occupied cell of `grid` within `half_angle` (rad) of
// `heading` (map frame) and `horizon` metres; infinity when there is none.
double NearestInCone(const OccupancyGrid& grid, const Point2& origin, double heading, double half_angle,
                     double horizon);

}  // namespace navd::navigation
