#include "services/common/relative_pose_error.h"

#include <cmath>

#include "services/common/error.h"

namespace navd {

RelativeError RelativePoseError(const std::vector<Pose2>& estimate, const std::vector<Pose2>& truth, int step) {
  if (step < 1 || estimate.size() != truth.size() || estimate.size() <= static_cast<size_t>(step))
    throw Error(ErrorCode::kInvalidArgument,
                "relative pose error needs two equally long trajectories of more poses than the step (>= 1)");
  RelativeError out;
  double sq_translation = 0.0, sq_rotation = 0.0;
  for (size_t i = 0; i + step < estimate.size(); ++i) {
    const Pose2 estimated = estimate[i].inverse() * estimate[i + step];
    const Pose2 true_step = truth[i].inverse() * truth[i + step];
    const Pose2 error = true_step.inverse() * estimated;
    const double translation = std::hypot(error.x, error.y);
    const double rotation = std::abs(NormalizeAngle(error.theta));
    out.translation_mean += translation;
    out.rotation_mean += rotation;
    sq_translation += translation * translation;
    sq_rotation += rotation * rotation;
    ++out.relations;
  }
  const double n = static_cast<double>(out.relations);
  out.translation_mean /= n;
  out.rotation_mean /= n;
  out.translation_rmse = std::sqrt(sq_translation / n);
  out.rotation_rmse = std::sqrt(sq_rotation / n);
  return out;
}

}  // namespace navd
