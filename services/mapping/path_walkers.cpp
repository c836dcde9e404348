#include "services/mapping/path_walkers.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "services/common/error.h"

namespace navd::mapping {

PathWalkers::PathWalkers(const std::vector<Pose2>& path, const std::vector<double>& stamps,
                         const PathWalkerOptions& options)
    : o_(options) {
  if (path.empty() || path.size() != stamps.size())
    throw Error(ErrorCode::kInvalidArgument, "walkers: the path needs poses, and a stamp for each");
  if (!(o_.count >= 0) || !(o_.radius >= 0.0) || !(o_.speed >= 0.0) || !(o_.side >= 0.0) || !(o_.clearance >= 0.0))
    throw Error(ErrorCode::kInvalidArgument, "walkers: count, radius, speed, side and clearance must be >= 0");
  t0_ = stamps.front();
  points_.reserve(path.size());
  arc_.reserve(path.size());
  for (const Pose2& p : path) {
    const Point2 q = p.translation();
    // Turns on the spot add no length: consecutive points are kept only where the path moved.
    if (!points_.empty() && (q - points_.back()).norm() < 1e-6) continue;
    arc_.push_back(points_.empty() ? 0.0 : arc_.back() + (q - points_.back()).norm());
    points_.push_back(q);
  }
  std::mt19937_64 rng(o_.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < o_.count; ++i) {
    Walker w;
    w.start = unit(rng) * path_length();
    w.pace = o_.speed * (0.7 + 0.6 * unit(rng)) * (unit(rng) < 0.5 ? -1.0 : 1.0);
    w.side = o_.side * (2.0 * unit(rng) - 1.0);
    walkers_.push_back(w);
  }
}

Point2 PathWalkers::PointAt(double along, double side) const {
  if (points_.size() == 1) return points_.front();
  const size_t k = std::min<size_t>(
      static_cast<size_t>(std::upper_bound(arc_.begin(), arc_.end(), along) - arc_.begin()), arc_.size() - 1);
  const size_t a = k == 0 ? 0 : k - 1;
  const Point2 dir = (points_[a + 1] - points_[a]) / (arc_[a + 1] - arc_[a]);
  const Point2 left(-dir.y(), dir.x());
  return points_[a] + (along - arc_[a]) * dir + side * left;
}

std::vector<Disc> PathWalkers::At(double t, const Point2& scanner) const {
  std::vector<Disc> out;
  const double length = path_length();
  for (size_t i = 0; i < walkers_.size(); ++i) {
    const Walker& w = walkers_[i];
    // Back and forth between the path's ends: a triangle wave of period twice its length.
    double along = length > 0.0 ? std::fmod(w.start + w.pace * (t - t0_), 2.0 * length) : 0.0;
    if (along < 0.0) along += 2.0 * length;
    if (along > length) along = 2.0 * length - along;
    const Point2 centre = PointAt(along, w.side);
    if ((centre - scanner).norm() < o_.radius + o_.clearance) continue;
    out.push_back({centre, o_.radius, static_cast<int>(i)});
  }
  return out;
}

}  // namespace navd::mapping
