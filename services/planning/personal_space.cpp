#include "services/planning/personal_space.h"

#include <cmath>

namespace navd::planning {

double PersonCostModel::Cost(const Point2& p, const Point2& mu, const Point2& v) const {
  const Point2 d = p - mu;
  // The person's frame: "ahead" along the walking direction; a standing person is treated as
  // facing the robot (both front terms apply all round).
  const double speed = v.norm();
  double ahead, side;
  bool front;
  if (speed > 0.1) {
    const Point2 f = v / speed;
    ahead = d.dot(f);
    side = f.x() * d.y() - f.y() * d.x();
    front = ahead >= 0.0;
  } else {
    ahead = d.norm();
    side = 0.0;
    front = true;
  }
  auto gauss = [](double a, double sa, double s, double ss) {
    return std::exp(-0.5 * (a * a / (sa * sa) + s * s / (ss * ss)));
  };
  double g = perpendicular_weight * gauss(ahead, perpendicular_sigma_ahead, side, perpendicular_sigma_side);
  if (front)
    g += parallel_weight * gauss(ahead, parallel_sigma_ahead, side, parallel_sigma_side);
  else
    g += rear_weight * gauss(ahead, rear_sigma, side, rear_sigma);
  g += interest * attractor_weight * gauss(ahead, attractor_sigma, side, attractor_sigma);
  return g;
}

}  // namespace navd::planning
