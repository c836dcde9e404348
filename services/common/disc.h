#pragma once
// Round bodies that lasers see: robots, people and moving obstacles (the simulator's, and the people
// a rendered log's scanner passes) are discs. Metres, map frame.
#include <vector>

#include "services/common/pose2.h"
#include "services/common/ray_caster.h"

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

// Distance along the unit vector `dir` from `origin` to the nearest of the static world and the discs (except
// `self`), at most max_range (also where the ray leaves the map: beyond its edge nothing reflects). Shared
// by the simulator's lasers and range sensors and the log renderer.
double CastAgainstWorld(const RayCaster& world, const std::vector<const Disc*>& nearby, const Point2& origin,
                        const Point2& dir, double max_range);
// The discs (except `self`) that a sensor at `origin` with reach `max_range` could see.
std::vector<const Disc*> DiscsWithin(const std::vector<Disc>& discs, const Point2& origin, double max_range, int self);

}  // namespace navd
