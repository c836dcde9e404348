#include "services/localization/localizer.h"

#include <cmath>

#include "services/common/error.h"

namespace navd::localization {

void Localizer::SetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  if (!std::isfinite(pose.x)) throw Error(ErrorCode::kInvalidArgument, "pose.x is not a finite number");
  if (!std::isfinite(pose.y)) throw Error(ErrorCode::kInvalidArgument, "pose.y is not a finite number");
  if (!std::isfinite(pose.theta)) throw Error(ErrorCode::kInvalidArgument, "pose.theta is not a finite number");
  for (int i = 0; i < 9; ++i) {
    if (!std::isfinite(covariance(i / 3, i % 3))) {
      throw Error(ErrorCode::kInvalidArgument, "covariance[" + std::to_string(i) + "] is not finite");
    }
  }
  if (!covariance.isApprox(covariance.transpose(), 1e-9) || (covariance.diagonal().array() < 0).any()) {
    throw Error(ErrorCode::kInvalidArgument, "covariance must be symmetric with a non-negative diagonal");
  }
  ResetPose({pose.x, pose.y, NormalizeAngle(pose.theta)}, covariance);
}

bool Localizer::SearchAround(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  if (!CanSearch() || !pose.finite() || !covariance.allFinite() || (covariance.diagonal().array() < 0).any())
    return false;
  ResetForSearch({pose.x, pose.y, NormalizeAngle(pose.theta)}, covariance);
  return true;
}

}  // namespace navd::localization
