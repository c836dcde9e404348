#include "simulator/moving_obstacle.h"

#include <cmath>

namespace navd::sim {

MovingObstacle::MovingObstacle(MovingObstacleDescription description) : d_(std::move(description)) {
  cumulative_.push_back(0.0);
  for (size_t i = 0; i < d_.loop.size(); ++i) {
    length_ += Distance(d_.loop[i], d_.loop[(i + 1) % d_.loop.size()]);
    cumulative_.push_back(length_);
  }
  position_ = d_.loop.empty() ? Point2::Zero() : d_.loop.front();
}

Point2 MovingObstacle::PointAt(double s) const {
  if (length_ <= 0.0) return position_;
  s = std::fmod(s, length_);
  if (s < 0.0) s += length_;
  for (size_t i = 0; i < d_.loop.size(); ++i) {
    if (s <= cumulative_[i + 1]) {
      const double seg = cumulative_[i + 1] - cumulative_[i];
      const double f = seg > 0 ? (s - cumulative_[i]) / seg : 0.0;
      return d_.loop[i] + f * (d_.loop[(i + 1) % d_.loop.size()] - d_.loop[i]);
    }
  }
  return d_.loop.front();
}

void MovingObstacle::Advance(double dt) {
  const Point2 next = Peek(dt);
  velocity_ = (next - position_) / dt;
  const double length = length_ > 0 ? length_ : 1.0;
  s_ = std::fmod(s_ + direction_ * d_.speed * dt, length);
  if (s_ < 0.0) s_ += length;
  position_ = next;
  waited_ = 0.0;
}

void MovingObstacle::Hold(double dt) {
  velocity_ = Point2::Zero();
  waited_ += dt;
  if (d_.patience > 0.0 && waited_ >= d_.patience) {
    direction_ = -direction_;
    waited_ = 0.0;
  }
}

}  // namespace navd::sim
