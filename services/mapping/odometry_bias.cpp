#include "services/mapping/odometry_bias.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace navd::mapping {

OdometryBiasOptions RobotOdometryBias() {
  OdometryBiasOptions o;
  o.enabled = true;
  return o;
}

OdometryBias::OdometryBias(const OdometryBiasOptions& options) : o_(options) {}

Pose2 OdometryBias::Correct(const Pose2& step) const {
  const double travel = std::hypot(step.x, step.y);
  return {scale_ * step.x, scale_ * step.y, step.theta + turn_error_ * step.theta + drift_ * travel};
}

void OdometryBias::Observe(const Pose2& step, const Pose2& matched, bool translation_fixed, bool heading_fixed) {
  if (!o_.enabled) return;
  const double travel = std::hypot(step.x, step.y);
  // Every step driven fades the ones before, whether or not it says anything itself.
  const double fade = std::exp(-travel / o_.memory);
  matched_travel_ *= fade;
  travel_ *= fade;
  turn_normal_ *= fade;
  turn_rhs_ *= fade;
  if (travel < o_.min_step) return;
  const Pose2 predicted = Correct(step);

  if (translation_fixed && std::hypot(matched.x - predicted.x, matched.y - predicted.y) <= o_.outlier_xy) {
    // The matched step's length along the odometry's direction of travel.
    matched_travel_ += (matched.x * step.x + matched.y * step.y) / travel;
    travel_ += travel;
    scale_ = std::clamp((o_.prior_travel + matched_travel_) / (o_.prior_travel + travel_), 1.0 - o_.max_scale_error,
                        1.0 + o_.max_scale_error);
  }
  if (heading_fixed && std::abs(NormalizeAngle(matched.theta - predicted.theta)) <= o_.outlier_theta) {
    const Eigen::Vector2d a(step.theta, travel);
    turn_normal_ += a * a.transpose();
    turn_rhs_ += a * NormalizeAngle(matched.theta - step.theta);
    const Eigen::Matrix2d prior = Eigen::Vector2d(o_.prior_turn, o_.prior_travel).asDiagonal();
    const Eigen::Vector2d fit = (turn_normal_ + prior).inverse() * turn_rhs_;
    turn_error_ = std::clamp(fit.x(), -o_.max_turn_error, o_.max_turn_error);
    drift_ = std::clamp(fit.y(), -o_.max_drift, o_.max_drift);
  }
}

}  // namespace navd::mapping
