#include "services/navigation/sonar_stimuli.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace navd::navigation {

std::vector<SonarEcho> UnexplainedEchoes(const std::vector<SonarEcho>& echoes, const Pose2& pose, double rim,
                                         const std::vector<Point2>& local, const OccupancyGrid* map,
                                         const SonarReflex& reflex) {
  const SonarReflexOptions& o = reflex.options();
  const double horizon = o.remember_within + o.explained_tolerance;
  std::vector<SonarEcho> out;
  for (const SonarEcho& e : echoes) {
    if (reflex.GroupOf(e.angle) == SonarGroup::kNone || !(e.range < o.remember_within)) continue;
    const Point2 origin = rim * Point2(std::cos(e.angle), std::sin(e.angle));  // robot frame
    double known = std::numeric_limits<double>::infinity();
    // What the cone would echo from the map and from what the laser sees: the nearest of either
    // within it, widened by kConeSlack for the pose's error. Five rays across the cone missed a door
    // jamb's 10 cm face that the sonar met, and its echoes became obstacles in the doorway.
    constexpr double kConeSlack = 0.05;  // rad
    const double half_cone = o.sensor_cone / 2.0 + kConeSlack;
    if (map) known = NearestInCone(*map, pose * origin, pose.theta + e.angle, half_cone, horizon);
    for (const Point2& p : local) {
      const Point2 d = p - origin;
      if (d.norm() < known && std::abs(NormalizeAngle(std::atan2(d.y(), d.x()) - e.angle)) <= half_cone)
        known = d.norm();
    }
    if (e.range < known - o.explained_tolerance) out.push_back(e);
  }
  return out;
}

double NearestInCone(const OccupancyGrid& grid, const Point2& origin, double heading, double half_angle,
                     double horizon) {
  double nearest = std::numeric_limits<double>::infinity();
  const CellIndex lo = grid.CellOf(origin - Point2(horizon, horizon)),
                  hi = grid.CellOf(origin + Point2(horizon, horizon));
  for (int y = std::max(lo.y, 0); y <= std::min(hi.y, grid.height() - 1); ++y) {
    for (int x = std::max(lo.x, 0); x <= std::min(hi.x, grid.width() - 1); ++x) {
      const CellIndex c{x, y};
      if (!grid.IsOccupied(c)) continue;
      const double d = grid.DistanceToCell(origin, c);
      if (d >= nearest || d > horizon) continue;
      // A cell is in the cone when any of it is: its centre's bearing, widened by its half-diagonal.
      const Point2 to = grid.CellCenter(c) - origin;
      const double spread = to.norm() > 1e-9 ? std::asin(std::min(1.0, 0.71 * grid.resolution() / to.norm())) : M_PI;
      if (std::abs(NormalizeAngle(std::atan2(to.y(), to.x()) - heading)) <= half_angle + spread) nearest = d;
    }
  }
  return nearest;
}

}  // namespace navd::navigation
