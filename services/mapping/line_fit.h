#pragma once
// The straight line a neighbourhood of 2-D points draws: through their mean, across the direction
// in which they spread least (the principal direction of their covariance). Points are added as
// offsets from a point of interest (m), so the line comes out relative to it. The point-to-line
// matcher takes a reference point's normal from it, and the scan consistency a return's distance.
#include <cmath>
#include <optional>

#include "services/common/pose2.h"

namespace navd::mapping {

struct FittedLine {
  Point2 mean;    // m: a point of the line, relative to the point of interest
  Point2 normal;  // unit vector across the line
};

class LineFit {
 public:
  void Add(const Point2& offset) {
    sum_ += offset;
    outer_ += offset * offset.transpose();
    ++count_;
  }
  int count() const { return count_; }

  // The line, unless the points spread across it more than max_flatness of their spread along it
  // (a corner, a plant, a person) or do not spread at all. Needs at least two points.
  std::optional<FittedLine> Fit(double max_flatness) const {
    if (count_ < 2) return std::nullopt;
    const Point2 mean = sum_ / count_;
    const Eigen::Matrix2d cov = outer_ / count_ - mean * mean.transpose();
    // The 2 x 2 covariance's eigenvalues in closed form: mid -+ half, with half the distance
    // between them from the spread's difference and the cross term.
    const double a = cov(0, 0), b = cov(0, 1), c = cov(1, 1);
    const double mid = 0.5 * (a + c), diff = 0.5 * (a - c), half = std::hypot(diff, b);
    const double small = mid - half, large = mid + half;
    if (large <= 0.0 || small > max_flatness * large) return std::nullopt;
    // The small eigenvalue's eigenvector, (b, small - a) or (small - c, b): the one of the two
    // that does not vanish as b does (a line along x has its normal along y, and the other way).
    const Point2 normal = diff >= 0.0 ? Point2(b, -(diff + half)) : Point2(diff - half, b);
    return FittedLine{mean, normal.normalized()};
  }

 private:
  Point2 sum_ = Point2::Zero();
  Eigen::Matrix2d outer_ = Eigen::Matrix2d::Zero();
  int count_ = 0;
};

}  // namespace navd::mapping
