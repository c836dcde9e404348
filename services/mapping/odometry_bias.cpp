#include "services/mapping/odometry_bias.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "services/common/error.h"

namespace navd::mapping {

OdometryBiasOptions RobotOdometryBias() {
  OdometryBiasOptions o;
  o.enabled = true;
  return o;
}

OdometryBias::OdometryBias(const OdometryBiasOptions& options) : o_(options) {
  const OdometryBiasOptions& o = o_;
  if (!(o.min_step > 0) || !(o.min_turn > 0) || !(o.prior_travel > 0) || !(o.prior_turn > 0) || !(o.memory > 0))
    throw Error(ErrorCode::kInvalidArgument,
                "OdometryBiasOptions: min_step, min_turn, prior_travel, prior_turn and memory must be above 0");
  if (!(o.max_scale_error >= 0) || !(o.max_scale_error < 1) || !(o.max_drift >= 0) || !(o.max_turn_error >= 0) ||
      !(o.max_turn_error < 1) || !(o.outlier_xy > 0) || !(o.outlier_theta > 0))
    throw Error(ErrorCode::kInvalidArgument,
                "OdometryBiasOptions: max_scale_error and max_turn_error must lie in [0, 1), max_drift at or above 0, "
                "outlier_xy and outlier_theta above 0");
}

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
  const Pose2 predicted = Correct(step);

  if (translation_fixed && travel >= o_.min_step &&
      std::hypot(matched.x - predicted.x, matched.y - predicted.y) <= o_.outlier_xy) {
    // The matched step's length along the odometry's direction of travel.
    matched_travel_ += (matched.x * step.x + matched.y * step.y) / travel;
    travel_ += travel;
    scale_ = std::clamp((o_.prior_travel + matched_travel_) / (o_.prior_travel + travel_), 1.0 - o_.max_scale_error,
                        1.0 + o_.max_scale_error);
  }
  if (heading_fixed && (travel >= o_.min_step || std::abs(step.theta) >= o_.min_turn) &&
      std::abs(NormalizeAngle(matched.theta - predicted.theta)) <= o_.outlier_theta) {
    const double weight = 1.0 / std::max(travel, o_.min_step);
    const Eigen::Vector2d a(step.theta, travel);
    turn_normal_ += weight * a * a.transpose();
    turn_rhs_ += weight * a * NormalizeAngle(matched.theta - step.theta);
    const Eigen::Matrix2d prior = Eigen::Vector2d(o_.prior_turn, o_.prior_travel).asDiagonal();
    const Eigen::Vector2d fit = (turn_normal_ + prior).ldlt().solve(turn_rhs_);
    turn_error_ = std::clamp(fit.x(), -o_.max_turn_error, o_.max_turn_error);
    drift_ = std::clamp(fit.y(), -o_.max_drift, o_.max_drift);
  }
}

}  // namespace navd::mapping
