#pragma once
// Scan-to-map registration by Gauss-Newton on the likelihood field's distance: find the map pose
// that puts a scan's end points on the map's obstacle surfaces, minimising the Huber-weighted sum
// of squared surface distances (as Hector SLAM and Cartographer's Ceres matcher do on their grids).
// End points further from any surface than the outlier distance are left out: they are moving
// obstacles or unmapped clutter, not pose error (seed 000 §4.4's T_mo = 0.30 m). The outlier
// distance starts wider and shrinks as the fit converges, so a pose off by tens of centimetres
// still finds its walls. Metres, radians, map frame.
#include <Eigen/Core>
#include <vector>

#include "services/common/pose2.h"
#include "services/localization/likelihood_field.h"

namespace navd::localization {

struct ScanToMapFitOptions {
  int max_iterations = 30;
  double huber = 0.05;                    // m: residuals beyond weigh linearly, not quadratically
  double outlier_distance = 0.30;         // m: end points further from any surface are ignored
  double initial_outlier_distance = 1.0;  // m: the first iteration's, shrinking by 0.7 per iteration
  int min_points = 10;                    // fewer inliers than this: no fit
  // Beams of one scan are not independent (they share the pose error and the map's
  // discretisation): the least-squares covariance is scaled by this to be honest.
  double covariance_scale = 20.0;
  double min_sigma_xy = 0.005;     // m: floors on the reported standard deviations
  double min_sigma_theta = 0.003;  // rad
};

struct ScanToMapFitResult {
  bool ok = false;                                           // converged with enough inliers
  Pose2 pose;                                                // the fitted robot pose, map frame
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();  // of (x, y, theta)
  double rms = 0.0;                                          // m: root mean square surface distance of the inliers
  int inliers = 0;
  int points = 0;
  int iterations = 0;
};

class ScanToMapFit {
 public:
  ScanToMapFit(const LikelihoodField& field, const ScanToMapFitOptions& options = {}) : field_(field), o_(options) {}
  // `points`: scan end points in the robot frame; `initial`: the pose to start from.
  ScanToMapFitResult Fit(const std::vector<Point2>& points, const Pose2& initial) const;

 private:
  const LikelihoodField& field_;
  ScanToMapFitOptions o_;
};

}  // namespace navd::localization
