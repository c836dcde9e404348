#include "services/common/relative_pose_error.h"

#include <cmath>

#include "services/common/error.h"

namespace navd {

RelativeError RelativePoseError(const std::vector<Pose2>& estimate, const std::vector<Pose2>& truth, int step) {
  if (step < 1 || estimate.size() != truth.size() || estimate.size() <= static_cast<size_t>(step))
    throw Error(ErrorCode::kInvalidArgument,
                "relative pose error needs two equally long trajectories of more poses than the step (>= 1)");
  RelativeError out;
  double sq_translation = 0.0, sq_rotation = 0.0, sq_along = 0.0, sq_across = 0.0;
  for (size_t i = 0; i + step < estimate.size(); ++i) {
    const Pose2 estimated = estimate[i].inverse() * estimate[i + step];
    const Pose2 true_step = truth[i].inverse() * truth[i + step];
    // The step's translation error in its first frame, split by the true step's direction.
    const Point2 offset = estimated.translation() - true_step.translation();
    const double translation = offset.norm();
    const double rotation = std::abs(NormalizeAngle(estimated.theta - true_step.theta));
    out.translation_mean += translation;
    out.rotation_mean += rotation;
    sq_translation += translation * translation;
    sq_rotation += rotation * rotation;
    const double length = true_step.translation().norm();
    const Point2 travel = length > 1e-9 ? Point2(true_step.translation() / length) : Point2(1.0, 0.0);
    const double along = offset.dot(travel), across = travel.x() * offset.y() - travel.y() * offset.x();
    sq_along += along * along;
    sq_across += across * across;
    ++out.relations;
  }
  const double n = static_cast<double>(out.relations);
  out.translation_mean /= n;
  out.rotation_mean /= n;
  out.translation_rmse = std::sqrt(sq_translation / n);
  out.rotation_rmse = std::sqrt(sq_rotation / n);
  out.along_rmse = std::sqrt(sq_along / n);
  out.across_rmse = std::sqrt(sq_across / n);
  return out;
}

}  // namespace navd
