#pragma once
// Relative pose error: how far each step of an estimated trajectory differs from the same step of
// the ground truth, the relations metric of Kümmerle et al., "On measuring the accuracy of SLAM
// algorithms" (2009), with every pair of poses `step` apart as a relation. Unlike the absolute
// error after alignment (trajectory_alignment.h) it needs no common frame, and a bend in one place
// costs one relation rather than every pose beyond it: it judges the trajectory's local accuracy,
// where the absolute error judges its global shape. Metres, radians.
#include <vector>

#include "services/common/pose2.h"

namespace navd {

struct RelativeError {
  int relations = 0;
  // Over the relations: the mean of |translation| and |rotation| of truth_ij⁻¹ ∘ estimate_ij,
  // where pose_ij = pose_i⁻¹ ∘ pose_j (pose j in pose i's frame), and their RMS.
  double translation_mean = 0.0, translation_rmse = 0.0;  // m
  double rotation_mean = 0.0, rotation_rmse = 0.0;        // rad
  // The translation's RMS split along the true step's direction of travel (for a turn on the spot,
  // the heading it started from) and across it: a robot driving a bare corridor measures its step
  // along it by odometry alone, and errs along.
  double along_rmse = 0.0, across_rmse = 0.0;  // m
};

// Throws Error(kInvalidArgument) unless both trajectories hold the same number of poses, more than
// `step`, and step >= 1.
RelativeError RelativePoseError(const std::vector<Pose2>& estimate, const std::vector<Pose2>& truth, int step = 1);

}  // namespace navd
