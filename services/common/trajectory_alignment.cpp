#include "services/common/trajectory_alignment.h"

#include <algorithm>
#include <cmath>

#include "services/common/error.h"

namespace navd {
namespace {

// What both fits need of two equally long point sets: their centroids, and about them the sums
// of e·t and e×t (whose angle is the best rotation, whose length over the estimate's spread the
// best scale) and of |e|².
struct Moments {
  Point2 estimate_centre = Point2::Zero(), truth_centre = Point2::Zero();
  double dot = 0.0, cross = 0.0, spread = 0.0;
};

Moments MomentsOf(const std::vector<Point2>& estimate, const std::vector<Point2>& truth) {
  if (estimate.empty() || estimate.size() != truth.size())
    throw Error(ErrorCode::kInvalidArgument, "trajectory alignment needs two equally long, non-empty trajectories");
  Moments m;
  for (size_t i = 0; i < estimate.size(); ++i) {
    m.estimate_centre += estimate[i];
    m.truth_centre += truth[i];
  }
  m.estimate_centre /= static_cast<double>(estimate.size());
  m.truth_centre /= static_cast<double>(truth.size());
  for (size_t i = 0; i < estimate.size(); ++i) {
    const Point2 e = estimate[i] - m.estimate_centre, t = truth[i] - m.truth_centre;
    m.dot += e.dot(t);
    m.cross += e.x() * t.y() - e.y() * t.x();
    m.spread += e.squaredNorm();
  }
  return m;
}

// The rigid transform the moments give: the estimate's centroid turned onto the truth's.
Pose2 RigidFit(const Moments& m) {
  const double theta = std::atan2(m.cross, m.dot);
  const Point2 centre = Rotate(m.estimate_centre, theta);
  return {m.truth_centre.x() - centre.x(), m.truth_centre.y() - centre.y(), theta};
}

}  // namespace

Pose2 AlignTrajectory(const std::vector<Point2>& estimate, const std::vector<Point2>& truth) {
  return RigidFit(MomentsOf(estimate, truth));
}

TrajectoryError AlignedTrajectoryError(const std::vector<Pose2>& estimate, const std::vector<Pose2>& truth) {
  std::vector<Point2> e, t;
  for (const Pose2& p : estimate) e.push_back(p.translation());
  for (const Pose2& p : truth) t.push_back(p.translation());
  const Moments moments = MomentsOf(e, t);
  TrajectoryError out;
  out.alignment = RigidFit(moments);
  // Umeyama's scale: at the best rotation the correlation is |(dot, cross)|; the estimate scaled
  // by it over its spread about its centroid fits best.
  const double correlation = std::hypot(moments.dot, moments.cross);
  const double fit = moments.spread > 0.0 && correlation > 0.0 ? correlation / moments.spread : 1.0;
  out.scale = 1.0 / fit;
  double sq = 0.0, sq_heading = 0.0, sq_similar = 0.0;
  for (size_t i = 0; i < estimate.size(); ++i) {
    const Pose2 aligned = out.alignment * estimate[i];
    const double d = Distance(aligned.translation(), truth[i].translation());
    const double h = NormalizeAngle(aligned.theta - truth[i].theta);
    sq += d * d;
    sq_heading += h * h;
    out.worst = std::max(out.worst, d);
    const Point2 scaled = fit * Rotate(e[i] - moments.estimate_centre, out.alignment.theta) + moments.truth_centre;
    sq_similar += (scaled - t[i]).squaredNorm();
  }
  const double n = static_cast<double>(estimate.size());
  out.position_rmse = std::sqrt(sq / n);
  out.heading_rmse = std::sqrt(sq_heading / n);
  out.similarity_rmse = std::sqrt(sq_similar / n);
  return out;
}

}  // namespace navd
