#pragma once
// A scripted moving obstacle (seed 000 Run 2): a disc that loops along a closed polyline at a
// constant speed, and waits while a body blocks its way. Metres, seconds, map frame.
#include <string>
#include <vector>

#include "services/common/pose2.h"

namespace navd::sim {

struct MovingObstacleDescription {
  std::string name;
  double radius = 0.20;             // m
  double speed = 0.30;              // m/s
  std::vector<Point2> loop;         // closed: the last point connects back to the first
};

class MovingObstacle {
 public:
  explicit MovingObstacle(MovingObstacleDescription description);

  // Where it would be after dt if unobstructed; Advance(dt) commits that move.
  Point2 Peek(double dt) const { return PointAt(s_ + d_.speed * dt); }
  void Advance(double dt);
  void Hold() { velocity_ = Point2::Zero(); }

  const Point2& position() const { return position_; }
  const Point2& velocity() const { return velocity_; }
  const MovingObstacleDescription& description() const { return d_; }
  double loop_length() const { return length_; }

 private:
  Point2 PointAt(double s) const;

  MovingObstacleDescription d_;
  std::vector<double> cumulative_;  // arc length at each vertex
  double length_ = 0.0;
  double s_ = 0.0;
  Point2 position_;
  Point2 velocity_ = Point2::Zero();
};

}  // namespace navd::sim
