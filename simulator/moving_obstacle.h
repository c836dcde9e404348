#pragma once
// A scripted moving obstacle (seed 000 Run 2): a disc that loops along a closed polyline at a
// constant speed, and waits while a body blocks its way; with `patience`, after waiting that long
// it turns back along its loop, as a person pushing a cart would rather than wait for ever.
// Metres, seconds, map frame.
#include <string>
#include <vector>

#include "services/common/pose2.h"

namespace navd::sim {

struct MovingObstacleDescription {
  std::string name;
  double radius = 0.20;      // m
  double speed = 0.30;       // m/s
  std::vector<Point2> loop;  // closed: the last point connects back to the first
  double patience = 0.0;     // s blocked before turning back; 0: waits for ever
};

class MovingObstacle {
 public:
  explicit MovingObstacle(MovingObstacleDescription description);

  // Where it would be after dt if unobstructed; Advance(dt) commits that move.
  Point2 Peek(double dt) const { return PointAt(s_ + direction_ * d_.speed * dt); }
  void Advance(double dt);
  // Blocked for this step of dt seconds.
  void Hold(double dt);

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
  double direction_ = 1.0;  // +1 along the loop, -1 back
  double waited_ = 0.0;     // s blocked in a row
  Point2 position_;
  Point2 velocity_ = Point2::Zero();
};

}  // namespace navd::sim
