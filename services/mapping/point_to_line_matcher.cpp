#include "services/mapping/point_to_line_matcher.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "services/mapping/line_fit.h"

namespace navd::mapping {
namespace {

// The information of the prior on the starting pose: x, y (1/m²), theta (1/rad²).
Eigen::Vector3d PriorInformation(const PointToLineOptions& o) {
  return {1.0 / (o.prior_sigma_xy * o.prior_sigma_xy), 1.0 / (o.prior_sigma_xy * o.prior_sigma_xy),
          1.0 / (o.prior_sigma_theta * o.prior_sigma_theta)};
}

}  // namespace

PointToLineMatcher::PointToLineMatcher(std::vector<Point2> reference, const PointToLineOptions& options)
    : o_(options), cell_(std::max(options.max_pair_distance, options.normal_radius)), reference_(std::move(reference)) {
  // Bucket the points by cell: sort indices by key, then record each key's run.
  std::vector<std::pair<long long, int>> keyed;
  keyed.reserve(reference_.size());
  for (size_t i = 0; i < reference_.size(); ++i)
    keyed.emplace_back(Key(Cell(reference_[i].x()), Cell(reference_[i].y())), static_cast<int>(i));
  std::sort(keyed.begin(), keyed.end());
  order_.reserve(keyed.size());
  for (size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i].first != keyed[i - 1].first)
      cells_.push_back({keyed[i].first, {static_cast<int>(i), static_cast<int>(i)}});
    order_.push_back(keyed[i].second);
    cells_.back().second.second = static_cast<int>(i) + 1;
  }

  normals_.assign(reference_.size(), Point2::Zero());
  normal_known_.assign(reference_.size(), 0);
}

const Point2& PointToLineMatcher::Normal(int i) const {
  if (normal_known_[i]) return normals_[i];
  normal_known_[i] = 1;
  // The line through the point: the principal direction of its neighbours.
  const Point2& p = reference_[i];
  const double r2 = o_.normal_radius * o_.normal_radius;
  LineFit fit;
  ForEachNear(p, [&](int j) {
    const Point2 d = reference_[j] - p;
    if (d.squaredNorm() <= r2) fit.Add(d);
  });
  if (fit.count() < 3) return normals_[i];
  if (const std::optional<FittedLine> line = fit.Fit(o_.max_flatness)) normals_[i] = line->normal;
  return normals_[i];
}

template <typename Visit>
void PointToLineMatcher::ForEachNear(const Point2& p, Visit&& visit) const {
  const int cx = Cell(p.x()), cy = Cell(p.y());
  // A column's cells sit next to one another among the sorted keys (x in the high bits), so one
  // search per column finds its three runs; a column whose y crosses 0, where the keys' low bits
  // wrap, is searched again: the iterator always rests on the first key at or above the row's.
  // The runs are visited row by row (y outer), the order Nearest's ties and Normal's sums depend on.
  std::array<std::pair<int, int>, 9> runs{};
  auto search = [&](long long key) {
    return std::lower_bound(cells_.begin(), cells_.end(), key,
                            [](const auto& cell, long long k) { return cell.first < k; });
  };
  for (int col = 0; col < 3; ++col) {
    const int x = cx - 1 + col;
    auto it = search(Key(x, cy - 1));
    for (int row = 0; row < 3; ++row) {
      const long long key = Key(x, cy - 1 + row);
      if (row > 0 && key < Key(x, cy - 2 + row)) it = search(key);
      if (it != cells_.end() && it->first == key) runs[row * 3 + col] = (it++)->second;
    }
  }
  for (const auto& [begin, end] : runs)
    for (int k = begin; k < end; ++k) visit(order_[k]);
}

int PointToLineMatcher::Nearest(const Point2& p) const {
  int best = -1;
  double best_d2 = o_.max_pair_distance * o_.max_pair_distance;
  ForEachNear(p, [&](int j) {
    const double d2 = (reference_[j] - p).squaredNorm();
    if (d2 < best_d2 && !Normal(j).isZero()) {
      best_d2 = d2;
      best = j;
    }
  });
  return best;
}

WallShare WallShareOf(const Eigen::Matrix3d& mean_information, const PointToLineOptions& options, const Point2& along) {
  const Eigen::Vector3d prior = PriorInformation(options);
  const Eigen::Matrix3d covariance = (mean_information + Eigen::Matrix3d(prior.asDiagonal())).inverse();
  WallShare share;
  const double norm2 = along.squaredNorm();
  if (norm2 > 0.0) share.along = 1.0 - along.dot(covariance.topLeftCorner<2, 2>() * along) / norm2 * prior.x();
  share.heading = 1.0 - covariance(2, 2) * prior.z();
  return share;
}

PointToLineResult PointToLineMatcher::Match(const std::vector<Point2>& points, const Pose2& initial) const {
  PointToLineResult result;
  result.pose = initial;
  if (points.empty() || reference_.empty() || !initial.finite()) return result;
  const Eigen::Vector3d prior_information = PriorInformation(o_);
  const double point_information = 1.0 / (o_.point_sigma * o_.point_sigma);
  const double c2 = o_.cauchy_scale * o_.cauchy_scale;
  Pose2 pose = initial;
  for (int it = 0; it < o_.max_iterations; ++it) {
    const double c = std::cos(pose.theta), s = std::sin(pose.theta);
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    double squared = 0.0;
    int pairs = 0;
    for (const Point2& p : points) {
      const Point2 w(pose.x + c * p.x() - s * p.y(), pose.y + s * p.x() + c * p.y());
      const int j = Nearest(w);
      if (j < 0) continue;
      const Point2& n = Normal(j);
      const double r = n.dot(w - reference_[j]);
      const double weight = 1.0 / (1.0 + r * r / c2);
      // d(world point)/d(theta) = R'(theta) p.
      const Eigen::Vector3d jac(n.x(), n.y(), n.x() * (-s * p.x() - c * p.y()) + n.y() * (c * p.x() - s * p.y()));
      h += weight * jac * jac.transpose();
      g += weight * r * jac;
      squared += r * r;
      ++pairs;
    }
    result.pairs = pairs;
    if (pairs < o_.min_pairs) return result;
    result.rms = std::sqrt(squared / pairs);
    // The point terms as their mean, so the prior weighs the same however many points there are.
    const double scale = point_information / pairs;
    const Eigen::Vector3d offset(pose.x - initial.x, pose.y - initial.y, NormalizeAngle(pose.theta - initial.theta));
    Eigen::Matrix3d a = scale * h;
    result.mean_information = a;
    a.diagonal() += prior_information;
    const Eigen::Vector3d b = scale * g + prior_information.cwiseProduct(offset);
    const Eigen::Vector3d step = a.ldlt().solve(-b);
    if (!step.allFinite()) return result;
    pose = {pose.x + step.x(), pose.y + step.y(), NormalizeAngle(pose.theta + step.z())};
    if (step.head<2>().norm() < 1e-5 && std::abs(step.z()) < 1e-5) break;
  }
  result.ok = true;
  result.pose = pose;
  return result;
}

}  // namespace navd::mapping
