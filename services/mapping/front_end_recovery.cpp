#include "services/mapping/front_end_recovery.h"

#include <algorithm>
#include <cmath>

#include "services/common/error.h"

namespace navd::mapping {
namespace {

// Whether `pose` lies on the rim of `window` around `centre` (its last cell or angular step) or
// outside it: a fit the first search could not reach, or may have clipped.
bool Beyond(const Pose2& pose, const Pose2& centre, const ScanMatchOptions& window) {
  return std::max(std::abs(pose.x - centre.x), std::abs(pose.y - centre.y)) > window.window_xy - window.resolution ||
         std::abs(NormalizeAngle(pose.theta - centre.theta)) > window.window_theta - window.angle_step;
}

}  // namespace

FrontEndRecoveryOptions RobotOdometryRecovery() {
  FrontEndRecoveryOptions o;
  o.below_score = 0.6;
  return o;
}

FrontEndRecovery::FrontEndRecovery(const FrontEndRecoveryOptions& options) : o_(options) {
  if (!(o_.gate_angle_step_factor >= 1.0))
    throw Error(ErrorCode::kInvalidArgument, "front_recovery.gate_angle_step_factor must be at least 1");
  if (!(o_.gate_point_spacing > 0.0))
    throw Error(ErrorCode::kInvalidArgument, "front_recovery.gate_point_spacing must be above 0");
  if (o_.max_held < 0) throw Error(ErrorCode::kInvalidArgument, "front_recovery.max_held must not be negative");
}

FrontEndRecovery::Outcome FrontEndRecovery::Settle(const ScanMatch& match, bool confirmed) {
  Outcome out{match, false, std::nullopt};
  if (confirmed) out.held_fit = held_fit_;
  pending_ = false;
  held_ = 0;
  return out;
}

FrontEndRecovery::Outcome FrontEndRecovery::Check(const CorrelationGrid& local, const std::vector<Point2>& points,
                                                  const Pose2& predicted, const ScanMatchOptions& window,
                                                  const ScanMatch& match) {
  if (match.score >= o_.below_score) return Settle(match);
  if (pending_) {
    const ScanMatch corrected = MatchScan(local, points, predicted * pending_correction_, window);
    if (corrected.score > match.score + o_.min_gain) return Settle(corrected, true);
  }
  const double grow_xy = std::max(1.0, o_.window_xy / window.window_xy);
  const double grow_theta = std::max(1.0, o_.window_theta / window.window_theta);
  if (grow_xy == 1.0 && grow_theta == 1.0) return Settle(match);  // the first window was as wide
  const ScanMatchOptions wide = window.Widened(grow_xy, grow_theta);
  // Most poorly matched scans (a hall's sparse walls, a new room through a door) fit no better
  // elsewhere: a sparse pass over the wider window settles those for a tenth of the full search.
  ScanMatchOptions sparse = wide;
  sparse.angle_step *= o_.gate_angle_step_factor;
  const ScanMatch rough = MatchScan(local, ThinPoints(points, o_.gate_point_spacing), predicted, sparse);
  if (!Beyond(rough.pose, predicted, window)) return Settle(match);
  const ScanMatch wider = MatchScan(local, points, predicted, wide);
  if (wider.score <= match.score + o_.min_gain || !Beyond(wider.pose, predicted, window)) return Settle(match);
  const bool same = Distance(wider.pose.translation(), match.pose.translation()) <= o_.same_xy &&
                    std::abs(NormalizeAngle(wider.pose.theta - match.pose.theta)) <= o_.same_theta;
  if (same || held_ >= o_.max_held) return Settle(wider);
  pending_ = true;
  pending_correction_ = predicted.inverse() * wider.pose;
  held_fit_ = wider.pose;
  ++held_;
  return {match, true, std::nullopt};
}

}  // namespace navd::mapping
