#include "services/mapping/graph_slam.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "services/common/error.h"
#include "services/common/scan_reach.h"
#include "services/mapping/shared_places.h"
#include "services/mapping/surface_facing_check.h"

namespace navd::mapping {
namespace {

Eigen::Matrix3d Information(double sigma_xy, double sigma_theta) {
  return Eigen::Vector3d(1.0 / (sigma_xy * sigma_xy), 1.0 / (sigma_xy * sigma_xy), 1.0 / (sigma_theta * sigma_theta))
      .asDiagonal();
}

}  // namespace

GraphSlam::GraphSlam(const GraphSlamOptions& options)
    : o_(options), recovery_(options.front_recovery), odometry_bias_(options.odometry_bias) {
  // Refused here rather than at the first place seen through, scans into the run.
  if (o_.drop_seen_through) SharedPlaces check(o_.seen_through_support);
}

GraphSlam::NodeReturns GraphSlam::Returns(const RangeScan& scan) const {
  const double cut = ScanReach(scan.ranges, scan.range_max, {o_.usable_range, o_.far_usable_range, o_.min_near_echoes});
  const double reach = cut < o_.far_usable_range ? cut + o_.reference_extra_range : cut;
  NodeReturns out;
  out.reference = ThinPointsTo(ScanReturns(scan.ranges, scan.angle_min, scan.angle_increment, scan.range_max, reach),
                               o_.return_budget, o_.match_point_spacing);
  // Those matched are the reference's nearer than the cut (reach is never shorter): one pass of
  // trigonometry per scan, in beam order still. A reading exactly at the cut (logs written to the
  // centimetre hold 20.00 m) stays out, as it would by its range: the bound is a hair inside the
  // rounding of r cos a, r sin a.
  const double matched_bound = cut * cut * (1.0 - 1e-12);
  out.matched.reserve(out.reference.size());
  for (const Point2& p : out.reference)
    if (p.squaredNorm() < matched_bound) out.matched.push_back(p);
  return out;
}

ScanMatchOptions GraphSlam::FrontEndWindow(const Pose2& moved) const {
  const ScanMatchOptions& base = o_.sequential;
  const double travel = std::hypot(moved.x, moved.y);
  const OdometryNoise& noise = o_.odometry;
  const double grow_xy = std::max(1.0, o_.front_window_sigmas_xy * noise.translation * travel / base.window_xy);
  const double grow_theta = std::max(1.0, (o_.front_window_sigmas_heading * noise.rotation_per_metre * travel +
                                           o_.front_window_sigmas_turn * noise.translation * std::abs(moved.theta)) /
                                              base.window_theta);
  return base.Widened(grow_xy, grow_theta);
}

Eigen::Matrix3d GraphSlam::WallInformation(const Pose2& pose, const Eigen::Matrix3d& matched, double sigma_xy,
                                           double sigma_theta, double free_sigma_xy, double free_sigma_theta) {
  Eigen::Matrix3d base = Information(sigma_xy, sigma_theta);
  if (matched.isZero()) return base;
  // The polish's information is about the pose in the map frame; the edge's error is in the new
  // node's frame.
  Eigen::Matrix3d to_node = Eigen::Matrix3d::Identity();
  to_node.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(-pose.theta).toRotationMatrix();
  const Eigen::Matrix3d left_open =
      (to_node * matched * to_node.transpose() + Information(free_sigma_xy, free_sigma_theta)).inverse();
  return (left_open + base.inverse()).inverse();
}

void GraphSlam::LearnOdometryBias(int last, const Pose2& step, const Pose2& pose, const Eigen::Matrix3d& matched) {
  if (!o_.odometry_bias.enabled) return;
  const Pose2& from = graph_.nodes()[last];
  const WallShare share = WallShareOf(matched, o_.polish, Rotate(Point2(step.x, step.y), from.theta));
  odometry_bias_.Observe(step, from.inverse() * pose, share.along >= o_.bias_min_wall_share,
                         share.heading >= o_.bias_min_wall_share);
}

std::vector<Point2> GraphSlam::SeenThroughPoints() const {
  std::vector<Point2> out;
  for (int n = 0; n < nodes(); ++n)
    for (size_t i = 0; i < node_reference_points_[n].size(); ++i)
      if (node_seen_through_[n][i]) out.push_back(graph_.nodes()[n] * node_reference_points_[n][i]);
  return out;
}

std::vector<Point2> GraphSlam::NodePointsInMap(int first, int last) const {
  std::vector<Point2> out;
  for (int n = std::max(0, first); n <= last && n < nodes(); ++n) {
    const Pose2& pose = graph_.nodes()[n];
    const std::vector<Point2>& points = node_reference_points_[n];
    const std::vector<char>& seen_through = node_seen_through_[n];
    for (size_t i = 0; i < points.size(); ++i)
      if (!seen_through[i]) out.push_back(pose * points[i]);
  }
  return out;
}

void GraphSlam::MarkSeenThrough(int node) {
  node_seen_through_.emplace_back(node_reference_points_[node].size(), 0);
  if (!o_.drop_seen_through || node == 0) return;
  const int first = LocalMapFirst(node - 1);
  // Built only once a place was seen through: a scene that stands still needs none.
  std::optional<SharedPlaces> shared;
  auto seen_by_another = [&](const Point2& p, int seen) {
    if (!shared) {
      shared.emplace(o_.seen_through_support);
      for (int n = first; n <= node; ++n)
        for (const Point2& q : node_reference_points_[n]) shared->Add(graph_.nodes()[n] * q, n);
    }
    return shared->SeenByAnother(p, seen);
  };
  auto view = [&](int n) {
    const RangeScan& scan = node_scans_[n];
    return SeenThroughCheck(graph_.nodes()[n], scan.ranges, scan.angle_min, scan.angle_increment, scan.range_max,
                            o_.seen_through);
  };
  auto mark = [&](int seen, const SeenThroughCheck& viewer) {
    const Pose2& pose = graph_.nodes()[seen];
    const std::vector<Point2>& points = node_reference_points_[seen];
    std::vector<char>& flags = node_seen_through_[seen];
    for (size_t i = 0; i < points.size(); ++i) {
      if (flags[i]) continue;
      const Point2 p = pose * points[i];
      if (viewer.SawThrough(p) && !seen_by_another(p, seen)) flags[i] = 1;
    }
  };
  const SeenThroughCheck newest = view(node);
  for (int m = first; m < node; ++m) {
    mark(node, view(m));
    mark(m, newest);
  }
}

int GraphSlam::LocalMapFirst(int last) const {
  int first = std::max(0, last - o_.local_map_nodes + 1);
  while (first > 0 && last - first + 1 < o_.local_map_max_nodes &&
         node_distance_[last] - node_distance_[first - 1] <= o_.local_map_travel)
    --first;
  return first;
}

Pose2 GraphSlam::AddScan(const Pose2& odometry, const RangeScan& scan) {
  if (!odometry.finite()) throw Error(ErrorCode::kInvalidArgument, "odometry pose is not finite");
  if (graph_.nodes().empty()) {
    graph_.AddNode(o_.first_pose);
    node_scans_.push_back(scan);
    NodeReturns returns = Returns(scan);
    node_points_.push_back(std::move(returns.matched));
    node_reference_points_.push_back(std::move(returns.reference));
    MarkSeenThrough(0);
    node_odometry_.push_back(odometry);
    node_distance_.push_back(0.0);
    node_scan_.push_back(0);
    scan_node_.push_back(0);
    scan_offset_.emplace_back();
    return o_.first_pose;
  }
  const int last = nodes() - 1;
  const Pose2 odometry_step = node_odometry_[last].inverse() * odometry;
  const Pose2 moved = odometry_bias_.Correct(odometry_step);
  const Pose2 predicted = graph_.nodes()[last] * moved;
  // A scan too close to the last node to add anything, or one the front end holds back, is
  // carried by odometry.
  auto carry = [&] {
    scan_node_.push_back(last);
    scan_offset_.push_back(moved);
    return predicted;
  };
  if (std::hypot(moved.x, moved.y) < o_.node_travel && std::abs(moved.theta) < o_.node_turn) return carry();

  // Front end: the scan against the local map of recent nodes, around the odometry's prediction.
  NodeReturns returns = Returns(scan);
  std::vector<Point2>& points = returns.matched;
  std::vector<Point2> local_points = NodePointsInMap(LocalMapFirst(last), last);
  const CorrelationGrid local(local_points, o_.sequential.resolution, o_.sequential.sigma);
  const std::vector<Point2> thinned = ThinPoints(points, o_.match_point_spacing);
  const ScanMatchOptions window = FrontEndWindow(moved);
  const FrontEndRecovery::Outcome checked =
      recovery_.Check(local, thinned, predicted, window, MatchScan(local, thinned, predicted, window));
  if (checked.held) {
    held_scan_ = static_cast<int>(scan_node_.size());
    return carry();
  }
  // The scan held just before, confirmed: its pose is its wider fit, not the odometry's.
  if (checked.held_fit) scan_offset_[held_scan_] = graph_.nodes()[last].inverse() * *checked.held_fit;
  const ScanMatch& match = checked.match;
  // A scan that explains too little of the local map (empty scan, a new room seen through a door)
  // keeps the odometry's prediction.
  Eigen::Matrix3d matched = Eigen::Matrix3d::Zero();
  const Pose2 pose =
      match.score > 0.1 ? Polish(std::move(local_points), points, match.pose, o_.polish, &matched) : predicted;
  LearnOdometryBias(last, odometry_step, pose, matched);
  const double step = Distance(pose.translation(), graph_.nodes()[last].translation());
  travel_since_closure_ += step;
  node_distance_.push_back(node_distance_.back() + step);
  const int node = graph_.AddNode(pose);
  graph_.AddEdge({last, node, graph_.nodes()[last].inverse() * pose,
                  WallInformation(pose, matched, o_.sequential_sigma_xy, o_.sequential_sigma_theta,
                                  o_.sequential_free_sigma_xy, o_.sequential_free_sigma_theta),
                  false});
  node_scans_.push_back(scan);
  node_points_.push_back(std::move(points));
  node_reference_points_.push_back(std::move(returns.reference));
  MarkSeenThrough(node);
  node_odometry_.push_back(odometry);
  node_scan_.push_back(static_cast<int>(scan_node_.size()));
  scan_node_.push_back(node);
  scan_offset_.emplace_back();
  TryLoopClosure(node);
  return graph_.nodes()[node];
}

void GraphSlam::TryLoopClosure(int node) {
  const Pose2 here = graph_.nodes()[node];
  int candidate = -1;
  double nearest = o_.loop_search_radius;
  for (int j = 0; j + o_.loop_min_node_gap <= node; ++j) {
    const double d = Distance(graph_.nodes()[j].translation(), here.translation());
    if (d < nearest) {
      nearest = d;
      candidate = j;
    }
  }
  if (candidate < 0) return;
  const std::vector<Point2> scan = ThinPoints(node_points_[node], o_.match_point_spacing);
  if (static_cast<int>(scan.size()) < o_.loop_min_points) return;
  ++loop_attempts_;
  const int first = std::max(0, candidate - o_.loop_neighbourhood);
  const int last = std::min(node - o_.loop_min_node_gap, candidate + o_.loop_neighbourhood);
  LoopReference reference{NodePointsInMap(first, last), {}};
  // The gate and the window reach as far as the chain can have drifted since the last closure;
  // failing that, as far as it can have drifted since it left the candidate (back at the end of a
  // loop that the closures on the way did not hold rigid).
  const double narrow = o_.loop_max_correction + o_.loop_correction_per_metre * travel_since_closure_;
  const double wide = std::min(
      o_.loop_wide_max_correction,
      o_.loop_max_correction + o_.loop_correction_per_metre * (node_distance_[node] - node_distance_[candidate]));
  ScanMatch match;
  if (!LoopMatch(reference, scan, node, narrow, false, &match) &&
      !(wide > narrow && LoopMatch(reference, scan, node, wide, true, &match)))
    return;
  // The correlative score rewards points that land near the candidate's; a corner or corridor
  // matched from behind fits as well, and only the walls' facing tells.
  if (BehindShare(first, last, node_points_[node], match.pose) > o_.loop_max_behind) return;

  const Pose2 relative = graph_.nodes()[candidate].inverse() * match.pose;
  graph_.AddEdge({candidate, node, relative, Information(o_.loop_sigma_xy, o_.loop_sigma_theta), true});
  closures_.push_back(
      {node_scan_[candidate], node_scan_[node], relative, match.score, graph_.edges().back().information});
  travel_since_closure_ = 0.0;
  unsettled_error_ += graph_.SquaredError(graph_.edges().back());
  if (unsettled_error_ > o_.loop_settled_error) Optimize();
}

void GraphSlam::Optimize() {
  graph_.Optimize(o_.optimizer);
  unsettled_error_ = 0.0;
  ++optimisations_;
}

ScanMatch GraphSlam::CoarseLoopMatch(LoopReference& reference, const std::vector<Point2>& scan, const Pose2& here,
                                     double allowance, bool wide_first, ScanMatch* ambiguity) const {
  ScanMatchOptions coarse = o_.sequential;
  coarse.resolution = 2.0 * o_.sequential.resolution;
  coarse.sigma = 2.0 * o_.sequential.sigma;
  coarse.window_xy = std::min(o_.loop_window_xy, allowance + coarse.resolution);
  coarse.window_theta = o_.loop_window_theta;
  coarse.angle_step = 2.0 * o_.sequential.angle_step;
  coarse.prior_sigma_xy = coarse.prior_sigma_theta = 0.0;  // a closure corrects drift: no pull back to it
  coarse.refine_candidates = 3;
  coarse.distinct_xy = o_.loop_distinct_xy;
  coarse.distinct_theta = o_.loop_distinct_theta;
  if (!wide_first) {
    *ambiguity = MatchScan(reference.Grid(1, o_.sequential), scan, here, coarse);
    return *ambiguity;
  }
  // A wide window first on a grid twice as coarse again (a quarter of the poses at half the
  // angles), which judges the ambiguity over all of it; then the 10 cm search around its best.
  ScanMatchOptions wide = coarse;
  wide.resolution *= 2.0;
  wide.sigma *= 2.0;
  wide.angle_step *= 2.0;
  *ambiguity = MatchScan(reference.Grid(2, o_.sequential), scan, here, wide);
  coarse.window_xy = 2.0 * wide.resolution;
  coarse.window_theta = 2.0 * wide.angle_step;
  coarse.distinct_xy = coarse.distinct_theta = 0.0;
  return MatchScan(reference.Grid(1, o_.sequential), scan, ambiguity->pose, coarse);
}

bool GraphSlam::LoopMatch(LoopReference& reference, const std::vector<Point2>& scan, int node, double allowance,
                          bool wide, ScanMatch* match) const {
  const Pose2 here = graph_.nodes()[node];
  ScanMatch ambiguity;
  const ScanMatch rough = CoarseLoopMatch(reference, scan, here, allowance, wide, &ambiguity);
  ScanMatchOptions fine = o_.sequential;
  fine.prior_sigma_xy = fine.prior_sigma_theta = 0.0;
  fine.window_xy = 4.0 * o_.sequential.resolution;
  fine.window_theta = 4.0 * o_.sequential.angle_step;
  *match = MatchScan(reference.Grid(0, o_.sequential), scan, rough.pose, fine);
  if (match->score < o_.loop_min_score) return false;
  if (ambiguity.coarse_elsewhere > (wide ? o_.loop_wide_max_ambiguity : o_.loop_max_ambiguity) * ambiguity.coarse_best)
    return false;
  match->pose = Polish(reference.points, node_points_[node], match->pose, o_.loop_polish);
  return Distance(match->pose.translation(), here.translation()) <= allowance;
}

bool GraphSlam::MatchAgainst(const std::vector<Point2>& scan, const std::vector<Point2>& returns,
                             std::vector<Point2> reference, const Pose2& guess, const ScanMatchOptions& window,
                             ScanMatch* match, Eigen::Matrix3d* walls) const {
  *match = MatchScan(CorrelationGrid(reference, window.resolution, window.sigma), scan, guess, window);
  walls->setZero();
  if (match->score >= o_.loop_min_score && match->coarse_spread <= o_.refine_max_spread) {
    match->pose = Polish(std::move(reference), returns, match->pose, o_.loop_polish);
    return true;
  }
  // Partial: only the walls the polish pairs with say where the pose lies, from where the graph
  // put it.
  if (match->score < o_.refine_min_partial_score) return false;
  match->pose = Polish(std::move(reference), returns, guess, o_.loop_polish, walls);
  return !walls->isZero();
}

Pose2 GraphSlam::Polish(std::vector<Point2> reference, const std::vector<Point2>& returns, const Pose2& guess,
                        const PointToLineOptions& options, Eigen::Matrix3d* information) const {
  const PointToLineResult polished = PointToLineMatcher(std::move(reference), options).Match(returns, guess);
  if (information) information->setZero();
  if (!polished.ok || Distance(polished.pose.translation(), guess.translation()) > o_.polish_max_shift_xy ||
      std::abs(NormalizeAngle(polished.pose.theta - guess.theta)) > o_.polish_max_shift_theta)
    return guess;
  if (information) *information = polished.mean_information;
  return polished.pose;
}

double GraphSlam::BehindShare(int first, int last, const std::vector<Point2>& returns, const Pose2& pose) const {
  std::vector<PlacedReturns> reference;
  for (int n = first; n <= last; ++n) reference.push_back({graph_.nodes()[n], &node_points_[n]});
  return SurfaceFacingCheck(reference).BehindShare(pose, returns);
}

bool GraphSlam::TurnedOnTheSpot(int node) const {
  if (node == 0) return false;
  const Pose2 moved = node_odometry_[node - 1].inverse() * node_odometry_[node];
  return std::abs(moved.theta) >= o_.refine_spot_turn && std::hypot(moved.x, moved.y) <= o_.refine_spot_travel;
}

void GraphSlam::Refine() {
  // Each node is matched where the graph puts it, with every closure so far.
  if (unsettled_error_ > 0.0) Optimize();
  const size_t kept = graph_.edges().size();
  ScanMatchOptions window = o_.sequential;
  window.window_xy = o_.refine_window_xy;
  window.window_theta = o_.refine_window_theta;
  window.prior_sigma_xy = window.prior_sigma_theta = 0.0;
  // The matcher measures coarse_spread while it judges ambiguity; nothing else of that is used here.
  window.distinct_xy = o_.loop_distinct_xy;
  const Eigen::Matrix3d information = Information(o_.loop_sigma_xy, o_.loop_sigma_theta);
  for (int pass = 0; pass < o_.refine_passes; ++pass) {
    graph_.TruncateEdges(kept);
    refinements_.clear();
    for (int i = 0; i < nodes(); ++i) {
      if (TurnedOnTheSpot(i)) continue;
      const std::vector<Point2> scan = ThinPoints(node_points_[i], o_.match_point_spacing);
      if (static_cast<int>(scan.size()) < o_.loop_min_points) continue;
      const Pose2 here = graph_.nodes()[i];
      auto distance = [&](int j) { return Distance(graph_.nodes()[j].translation(), here.translation()); };
      // Stretches: runs of consecutive nodes within the radius, each as (its nearest node, first, last).
      std::vector<std::array<int, 3>> stretches;
      const int last_j = i - o_.local_map_nodes;
      for (int j = 0; j < last_j;) {
        if (distance(j) >= o_.refine_radius) {
          ++j;
          continue;
        }
        int nearest = j, k = j;
        for (; k < last_j && distance(k) < o_.refine_radius; ++k)
          if (distance(k) < distance(nearest)) nearest = k;
        stretches.push_back(
            {nearest, std::max(j, nearest - o_.loop_neighbourhood), std::min(k - 1, nearest + o_.loop_neighbourhood)});
        j = k;
      }
      // The nearest stretches only: a node the robot passed many times is held well by a few.
      std::sort(stretches.begin(), stretches.end(), [&](const std::array<int, 3>& a, const std::array<int, 3>& b) {
        return distance(a[0]) < distance(b[0]);
      });
      if (static_cast<int>(stretches.size()) > o_.refine_max_stretches) stretches.resize(o_.refine_max_stretches);
      for (const auto& [nearest, first, last] : stretches) {
        if (TurnedOnTheSpot(nearest)) continue;
        ScanMatch match;
        Eigen::Matrix3d walls;
        if (!MatchAgainst(scan, node_points_[i], NodePointsInMap(first, last), here, window, &match, &walls)) continue;
        const Pose2 relative = graph_.nodes()[nearest].inverse() * match.pose;
        const Eigen::Matrix3d edge_information =
            walls.isZero() ? information
                           : WallInformation(match.pose, walls, o_.loop_sigma_xy, o_.loop_sigma_theta,
                                             o_.refine_partial_free_sigma, o_.refine_partial_free_sigma);
        graph_.AddEdge({nearest, i, relative, edge_information, true});
        refinements_.push_back({node_scan_[nearest], node_scan_[i], relative, match.score, edge_information});
      }
    }
    Optimize();
  }
}

std::vector<Pose2> GraphSlam::Trajectory() const {
  std::vector<Pose2> out;
  out.reserve(scan_node_.size());
  for (size_t k = 0; k < scan_node_.size(); ++k) out.push_back(graph_.nodes()[scan_node_[k]] * scan_offset_[k]);
  return out;
}

OccupancyGrid GraphSlam::RenderMap(const MapperOptions& options) const {
  if (graph_.nodes().empty()) throw Error(ErrorCode::kFailedPrecondition, "no scans mapped yet");
  Point2 lo = graph_.nodes().front().translation(), hi = lo;
  for (const Pose2& p : graph_.nodes()) {
    lo = lo.cwiseMin(p.translation());
    hi = hi.cwiseMax(p.translation());
  }
  const double reach = std::min(options.usable_range, o_.usable_range) + 1.0;
  lo -= Point2(reach, reach);
  hi += Point2(reach, reach);
  MapperOptions fitted = options;
  fitted.resolution = ResolutionToFit(lo, hi, options.resolution);
  OccupancyGridMapper mapper(lo, hi, fitted);
  RenderInto(mapper);
  return mapper.ToGrid();
}

void GraphSlam::RenderInto(OccupancyGridMapper& mapper) const {
  for (int n = 0; n < nodes(); ++n)
    mapper.AddScan(graph_.nodes()[n], node_scans_[n].ranges, node_scans_[n].angle_min, node_scans_[n].angle_increment,
                   node_scans_[n].range_max);
}

}  // namespace navd::mapping
