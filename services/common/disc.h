#pragma once
// Round bodies that lasers see: robots, people and moving obstacles (the simulator's, and the people
// a rendered log's scanner passes) are discs. Metres, map frame.
#include "services/common/pose2.h"

namespace navd {

// A disc in the world that sensors see and robots bump into (a robot, a person, a moving obstacle).
struct Disc {
  Point2 centre;
  double radius = 0.0;
  int id = -1;  // who it is (Simulation's body index), so a sensor can skip its own robot
};

// Distance along the unit direction `dir` from `origin` to where the ray enters `disc`, or
// infinity when it misses (or starts inside it).
double RayDiscDistance(const Point2& origin, const Point2& dir, const Disc& disc);

}  // namespace navd
