#pragma once
// Point-to-line scan matching (Censi's PL-ICP, the fine stage of most 2-D laser odometries): each
// scan point is paired with the nearest reference point, and the pose is moved to put the point on
// the line through that reference point (its normal from the reference points around it).
// Gauss-Newton with Cauchy weights, pairs made afresh each iteration.
//
// It polishes a pose the correlative matcher found: the correlative search scores a smeared grid
// of whole cells, so its answer is off by millimetres to a centimetre or two, and that error adds
// up scan after scan; the lines of the reference points hold the pose to the walls' true positions.
// Along a direction no line constrains (a bare corridor) the pose stays where it started: a prior
// on the starting pose carries it there. Map frame, metres, radians.
#include <vector>

#include "services/common/pose2.h"
#include "services/mapping/cell_key.h"

namespace navd::mapping {

struct PointToLineOptions {
  double max_pair_distance = 0.2;  // m: a scan point farther from every reference point is left out
  double normal_radius = 0.2;      // m: reference points this close to one shape its line
  // A reference point whose neighbours are not spread along a line (a corner, a lone point) has no
  // normal and pairs with nothing: the smaller spread over the larger, at most this.
  double max_flatness = 0.1;
  double point_sigma = 0.02;   // m: a point's distance to its line that counts as one sigma
  double cauchy_scale = 0.03;  // m: weights fall to a half at this distance
  // The prior on the starting pose, against the mean of the point terms: a direction the lines
  // constrain moves freely, a direction they do not stays.
  double prior_sigma_xy = 0.1;      // m
  double prior_sigma_theta = 0.05;  // rad
  int max_iterations = 15;
  int min_pairs = 20;
};

struct PointToLineResult {
  bool ok = false;  // converged with at least min_pairs pairs
  Pose2 pose;
  int pairs = 0;
  double rms = 0.0;  // m: root mean square point-to-line distance of the pairs
  // The information of one mean pair about the pose (map-frame x, y in 1/m², theta in 1/rad²),
  // at `pose`: its shape says which directions the walls constrain (along a bare corridor, none).
  Eigen::Matrix3d mean_information = Eigen::Matrix3d::Zero();
};

// How much of a polished pose its walls fixed rather than the prior on its start: for the
// direction `along` (map frame) and for the heading, 1 - the pose's variance with the pairs'
// information (`mean_information`, PointToLineResult's) over its variance under the prior alone.
// 0 where the prior alone holds it (along a bare corridor, or no pairs at all), towards 1 where
// walls do.
struct WallShare {
  double along = 0.0, heading = 0.0;
};
WallShare WallShareOf(const Eigen::Matrix3d& mean_information, const PointToLineOptions& options, const Point2& along);

// Reference points (map frame) with their lines, indexed for nearest-point queries.
class PointToLineMatcher {
 public:
  PointToLineMatcher(std::vector<Point2> reference, const PointToLineOptions& options = {});
  // `points`: scan points in the robot frame; `initial`: the robot pose to start from.
  PointToLineResult Match(const std::vector<Point2>& points, const Pose2& initial) const;

 private:
  long long Key(int cx, int cy) const { return CellKey(cx, cy); }
  int Cell(double v) const { return static_cast<int>(std::floor(v / cell_)); }
  // Indices of reference points in the 3 x 3 cells around p.
  template <typename Visit>
  void ForEachNear(const Point2& p, Visit&& visit) const;
  // The nearest reference point with a normal, within max_pair_distance; -1 when none.
  int Nearest(const Point2& p) const;

  PointToLineOptions o_;
  double cell_;
  std::vector<Point2> reference_;
  // A reference point's normal (unit; zero where it has none), worked out at its first use: a
  // match pairs its scan with a part of the reference only, and normals cost most of a polish.
  // A matcher is not to be shared between threads.
  const Point2& Normal(int i) const;
  mutable std::vector<Point2> normals_;
  mutable std::vector<char> normal_known_;
  std::vector<int> order_;                                        // reference indices grouped by cell
  std::vector<std::pair<long long, std::pair<int, int>>> cells_;  // sorted: key, [begin, end) in order_
};

}  // namespace navd::mapping
