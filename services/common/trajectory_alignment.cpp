#include "services/common/trajectory_alignment.h"

#include <cmath>

#include "services/common/error.h"

namespace navd {

Pose2 AlignTrajectory(const std::vector<Point2>& estimate, const std::vector<Point2>& truth) {
  if (estimate.empty() || estimate.size() != truth.size())
    throw Error(ErrorCode::kInvalidArgument, "trajectory alignment needs two equally long, non-empty trajectories");
  Point2 ce = Point2::Zero(), ct = Point2::Zero();
  for (size_t i = 0; i < estimate.size(); ++i) {
    ce += estimate[i];
    ct += truth[i];
  }
  ce /= static_cast<double>(estimate.size());
  ct /= static_cast<double>(truth.size());
  double dot = 0.0, cross = 0.0;
  for (size_t i = 0; i < estimate.size(); ++i) {
    const Point2 e = estimate[i] - ce, t = truth[i] - ct;
    dot += e.dot(t);
    cross += e.x() * t.y() - e.y() * t.x();
  }
  const double theta = std::atan2(cross, dot);
  const double c = std::cos(theta), s = std::sin(theta);
  return {ct.x() - (c * ce.x() - s * ce.y()), ct.y() - (s * ce.x() + c * ce.y()), theta};
}

TrajectoryError AlignedTrajectoryError(const std::vector<Pose2>& estimate, const std::vector<Pose2>& truth) {
  std::vector<Point2> e, t;
  for (const Pose2& p : estimate) e.push_back(p.translation());
  for (const Pose2& p : truth) t.push_back(p.translation());
  TrajectoryError out;
  out.alignment = AlignTrajectory(e, t);
  double sq = 0.0, sq_heading = 0.0;
  for (size_t i = 0; i < estimate.size(); ++i) {
    const Pose2 aligned = out.alignment * estimate[i];
    const double d = Distance(aligned.translation(), truth[i].translation());
    const double h = NormalizeAngle(aligned.theta - truth[i].theta);
    sq += d * d;
    sq_heading += h * h;
    out.worst = std::max(out.worst, d);
  }
  const double n = static_cast<double>(estimate.size());
  out.position_rmse = std::sqrt(sq / n);
  // The least-squares scale about the centroids (Umeyama): the rigid fit's correlation over the
  // estimate's spread; the rigid rotation stays the best one at any scale.
  Point2 ce = Point2::Zero(), ct = Point2::Zero();
  for (size_t i = 0; i < e.size(); ++i) {
    ce += e[i];
    ct += t[i];
  }
  ce /= n;
  ct /= n;
  double correlation = 0.0, spread = 0.0;
  for (size_t i = 0; i < e.size(); ++i) {
    correlation += Rotate(e[i] - ce, out.alignment.theta).dot(t[i] - ct);
    spread += (e[i] - ce).squaredNorm();
  }
  const double fit = spread > 0.0 && correlation > 0.0 ? correlation / spread : 1.0;
  out.scale = 1.0 / fit;
  double sq_similar = 0.0;
  for (size_t i = 0; i < e.size(); ++i)
    sq_similar += (fit * Rotate(e[i] - ce, out.alignment.theta) + ct - t[i]).squaredNorm();
  out.similarity_rmse = std::sqrt(sq_similar / n);
  out.heading_rmse = std::sqrt(sq_heading / n);
  return out;
}

}  // namespace navd
