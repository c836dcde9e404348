#include "services/common/odometry_noise.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace navd {

OdometryNoise ParseOdometryNoise(const std::string& text, const std::string& option) {
  OdometryNoise n;
  // The whole text read as two fields or as four, nothing left over.
  int two_end = -1, four_end = -1;
  const int read = std::sscanf(text.c_str(), "%lf,%lf%n,%lf,%lf%n", &n.translation, &n.rotation_per_metre, &two_end,
                               &n.scale_error, &n.drift, &four_end);
  const int size = static_cast<int>(text.size());
  const bool whole = (read == 2 && two_end == size) || (read == 4 && four_end == size);
  if (!whole || !(n.translation >= 0) || !(n.rotation_per_metre >= 0) || !std::isfinite(n.translation) ||
      !std::isfinite(n.rotation_per_metre) || !(n.scale_error > -1.0) || !std::isfinite(n.scale_error) ||
      !std::isfinite(n.drift)) {
    throw std::invalid_argument(option + " '" + text + "' is not T,R or T,R,S,D with T, R >= 0, S > -1");
  }
  return n;
}

Pose2 OdometryCorruptor::Next(const Pose2& truth) {
  if (!started_) {
    started_ = true;
    last_truth_ = truth;
    return odometry_;
  }
  const Pose2 step = last_truth_.inverse() * truth;
  last_truth_ = truth;
  const double dist = std::hypot(step.x, step.y);
  const double scale = (1.0 + noise_.scale_error) * (1.0 + noise_.translation * normal_(rng_));
  const double per_metre = noise_.drift * dist + noise_.rotation_per_metre * dist * normal_(rng_);
  const double per_turn = noise_.translation * std::abs(step.theta) * normal_(rng_);
  odometry_ = odometry_ * Pose2{step.x * scale, step.y * scale, step.theta + per_metre + per_turn};
  return odometry_;
}

}  // namespace navd
