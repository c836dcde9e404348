#include "services/localization/scan_to_map_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace navd::localization {
namespace {

// The normal equations of one Gauss-Newton step at `pose`, with its weighted cost.
struct Linearisation {
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  double cost = 0.0;     // truncated: an outlier costs what a point at the outlier distance does
  double squared = 0.0;  // unweighted sum of squared distances of the inliers
  int inliers = 0;
};

}  // namespace

ScanToMapFitResult ScanToMapFit::Fit(const std::vector<Point2>& points, const Pose2& initial) const {
  ScanToMapFitResult result;
  result.pose = initial;
  result.points = static_cast<int>(points.size());
  if (!initial.finite()) return result;
  auto linearise = [&](const Pose2& pose, double outlier) {
    Linearisation l;
    const double c = std::cos(pose.theta), s = std::sin(pose.theta);
    for (const Point2& p : points) {
      const Point2 w(pose.x + c * p.x() - s * p.y(), pose.y + s * p.x() + c * p.y());
      double d;
      Point2 grad;
      if (!field_.SurfaceDistance(w, &d, &grad) || std::abs(d) > outlier) continue;
      const double a = std::abs(d);
      const double weight = a <= o_.huber ? 1.0 : o_.huber / a;
      // d(world point)/d(theta) = R'(theta) p.
      const Eigen::Vector3d j(grad.x(), grad.y(),
                              grad.x() * (-s * p.x() - c * p.y()) + grad.y() * (c * p.x() - s * p.y()));
      l.h += weight * j * j.transpose();
      l.g += weight * d * j;
      l.cost += a <= o_.huber ? 0.5 * d * d : o_.huber * (a - 0.5 * o_.huber);
      l.squared += d * d;
      ++l.inliers;
    }
    // Points that leave the map or the outlier band still cost: otherwise a pose that pushes
    // points off the map's edge would look better for having fewer to explain.
    const double capped = outlier <= o_.huber ? 0.5 * outlier * outlier : o_.huber * (outlier - 0.5 * o_.huber);
    l.cost += capped * static_cast<double>(points.size() - l.inliers);
    return l;
  };
  Pose2 pose = initial;
  double outlier = std::max(o_.initial_outlier_distance, o_.outlier_distance);
  double lambda = 1e-3;
  Linearisation l = linearise(pose, outlier);
  for (int it = 0; it < o_.max_iterations; ++it) {
    result.iterations = it + 1;
    if (l.inliers < o_.min_points) return result;
    // Levenberg-Marquardt damping: a step that raises the cost is retried shorter.
    Eigen::Matrix3d damped = l.h;
    damped.diagonal() *= 1.0 + lambda;
    const Eigen::Vector3d step = damped.ldlt().solve(-l.g);
    if (!step.allFinite()) return result;
    const Pose2 next{pose.x + step.x(), pose.y + step.y(), NormalizeAngle(pose.theta + step.z())};
    const Linearisation ln = linearise(next, outlier);
    if (ln.inliers >= o_.min_points && ln.cost <= l.cost) {
      pose = next;
      lambda = std::max(lambda * 0.3, 1e-6);
      const bool small = step.head<2>().norm() < 1e-4 && std::abs(step.z()) < 1e-4;
      const double narrower = std::max(o_.outlier_distance, outlier * 0.7);
      if (narrower < outlier) {
        outlier = narrower;
        l = linearise(pose, outlier);
      } else {
        l = ln;
        if (small) break;
      }
    } else {
      lambda *= 10.0;
      if (lambda > 1e6) break;
    }
  }
  if (l.inliers < o_.min_points) return result;
  result.ok = true;
  result.pose = pose;
  result.inliers = l.inliers;
  result.rms = std::sqrt(l.squared / l.inliers);
  const double sigma2 = std::max(l.squared / std::max(1, l.inliers - 3), o_.min_sigma_xy * o_.min_sigma_xy);
  Eigen::Matrix3d cov = o_.covariance_scale * sigma2 * (l.h + 1e-9 * Eigen::Matrix3d::Identity()).inverse();
  cov(0, 0) = std::max(cov(0, 0), o_.min_sigma_xy * o_.min_sigma_xy);
  cov(1, 1) = std::max(cov(1, 1), o_.min_sigma_xy * o_.min_sigma_xy);
  cov(2, 2) = std::max(cov(2, 2), o_.min_sigma_theta * o_.min_sigma_theta);
  result.covariance = 0.5 * (cov + cov.transpose());
  return result;
}

}  // namespace navd::localization
