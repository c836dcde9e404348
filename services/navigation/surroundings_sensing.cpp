#include "services/navigation/surroundings_sensing.h"

#include <algorithm>
#include <cmath>

#include "services/navigation/free_way.h"

namespace navd::navigation {
namespace {

// Metres free behind the rim of a robot of `radius` at `pose` on `grid`, up to 1 m. The robot's
// whole disc is swept back, not one ray: a wall beside the robot's rim counts. Only walls behind
// its centre do: one the front touches now does not close the way back.
double RoomBehindOnMap(const OccupancyGrid& grid, const Pose2& pose, double radius) {
  const Point2 back(-std::cos(pose.theta), -std::sin(pose.theta));
  constexpr double kStep = 0.02, kHorizon = 1.0;
  const double r = radius + 0.03;  // the pose estimate is a few centimetres off
  auto hits = [&](const Point2& centre) {
    const CellIndex lo = grid.CellOf(centre - Point2(r, r)), hi = grid.CellOf(centre + Point2(r, r));
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        const CellIndex c{x, y};
        if (grid.DistanceToCell(centre, c) > r || (grid.CellCenter(c) - pose.translation()).dot(back) <= 0.0) continue;
        if (!grid.Contains(c) || grid.IsOccupied(c)) return true;
      }
    return false;
  };
  for (double d = kStep; d <= kHorizon; d += kStep)
    if (hits(pose.translation() + d * back)) return d - kStep;
  return kHorizon;
}

}  // namespace

void AddPredictedRim(const DetectedObstacle& o, const Pose2& pose, std::initializer_list<double> ahead,
                     std::vector<Point2>& out) {
  for (const double t : ahead) {
    const Point2 centre = pose.inverse() * (o.position + t * o.velocity);
    for (int k = 0; k < 8; ++k) {
      const double a = k * M_PI / 4.0;
      out.emplace_back(centre + o.radius * Point2(std::cos(a), std::sin(a)));
    }
  }
}

AvoidanceSensing SenseSurroundings(const Pose2& pose, double radius, std::vector<Point2> local,
                                   const OccupancyGrid* map, double rear_free,
                                   const std::vector<DetectedObstacle>& candidates,
                                   const std::vector<DetectedObstacle>& confirmed) {
  AvoidanceSensing sensing;
  // Behind the robot the laser is blind: the map says how far the wall is, the rear sensor the rest.
  if (map) rear_free = std::min(rear_free, RoomBehindOnMap(*map, pose, radius));
  // The laser is blind behind, but the obstacles it tracked are still known for a few scans: one
  // whose disc lies across the way back, now or within the next second, closes it (a cart crossing
  // behind a robot backing up enters its way beside the rear sensor's one ray).
  for (const DetectedObstacle& o : candidates) {
    for (const double t : {0.0, 0.5, 1.0}) {
      const Point2 p = pose.inverse() * (o.position + t * o.velocity);
      if (p.x() < 0.0 && std::abs(p.y()) < o.radius + radius)
        rear_free = std::min(rear_free, std::max(0.0, -p.x() - o.radius - radius));
    }
  }
  sensing.rear_free = rear_free;
  for (const Point2& p : local) sensing.nearest = std::min(sensing.nearest, p.norm() - radius);
  // Where the tracked obstacles will be in the next second also closes a way: a cart crossing it
  // from the side enters the corridor faster than the robot stops.
  for (const DetectedObstacle& o : confirmed) AddPredictedRim(o, pose, {0.5, 1.0}, local);
  sensing.free_along = FreeAlong(std::move(local), radius);
  return sensing;
}

}  // namespace navd::navigation
