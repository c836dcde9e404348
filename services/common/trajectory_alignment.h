#pragma once
// Absolute trajectory error after SE(2) alignment (the "ATE" of SLAM benchmarks): an estimate made
// in its own map frame is rotated and translated onto the ground truth by the closed-form least
// squares fit (Umeyama without scale), then the position RMSE is taken. Metres, radians.
// Beside it, the fit that may also scale the estimate (Umeyama with scale): a scale away from 1
// says the estimate's map is larger or smaller than the ground truth's as a whole, which the rigid
// fit counts as error growing with the distance from the trajectory's middle.
#include <vector>

#include "services/common/pose2.h"

namespace navd {

// The rigid transform T minimising sum |T * estimate[i] - truth[i]|^2 (both the same length, >= 1).
Pose2 AlignTrajectory(const std::vector<Point2>& estimate, const std::vector<Point2>& truth);

struct TrajectoryError {
  Pose2 alignment;             // estimate frame -> truth frame
  double position_rmse = 0.0;  // m
  double heading_rmse = 0.0;   // rad
  double worst = 0.0;          // m
  // The similarity fit (the same rotation, the estimate scaled about its centroid): how large the
  // estimate's map is against the truth's (1.01: 1 % larger), and the position RMSE once scaled.
  double scale = 1.0;
  double similarity_rmse = 0.0;  // m
};

TrajectoryError AlignedTrajectoryError(const std::vector<Pose2>& estimate, const std::vector<Pose2>& truth);

}  // namespace navd
