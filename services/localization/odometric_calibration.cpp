#include "services/localization/odometric_calibration.h"

#include <algorithm>
#include <cmath>

#include "services/localization/scan_points.h"

namespace navd::localization {
namespace {
// Odometry error growth of the reported covariance between anchorings, per metre driven.
constexpr double kVariancePerMetreXY = 0.02 * 0.02;
constexpr double kVariancePerMetreTheta = 0.02 * 0.02;
}  // namespace

OdometricCalibrationLocalizer::OdometricCalibrationLocalizer(const OccupancyGrid& map,
                                                             const OdometricCalibrationOptions& options,
                                                             const Pose2& initial_pose)
    : o_(options), map_(std::make_shared<const RayCaster>(map)), initial_pose_(initial_pose) {}

bool OdometricCalibrationLocalizer::SetMap(const OccupancyGrid& map) {
  auto caster = std::make_shared<const RayCaster>(map);
  std::lock_guard<std::mutex> lock(mutex_);
  map_ = std::move(caster);
  return true;
}

void OdometricCalibrationLocalizer::ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!have_odom_) {
    initial_pose_ = pose;
  } else {
    map_from_odom_ = pose * odom_history_.latest().pose.inverse();
  }
  anchor_covariance_ = covariance;
  anchor_distance_ = distance_;
}

void OdometricCalibrationLocalizer::AddOdometry(const OdometryReading& reading) {
  if (!reading.pose.finite()) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!have_odom_) {
    map_from_odom_ = initial_pose_ * reading.pose.inverse();
    have_odom_ = true;
  } else {
    const Pose2& last = odom_history_.latest().pose;
    distance_ += std::hypot(reading.pose.x - last.x, reading.pose.y - last.y);
  }
  odom_history_.Add(reading);
}

OdometricCalibrationLocalizer::Match OdometricCalibrationLocalizer::Compare(const std::vector<double>& angles,
                                                                            const std::vector<double>& ranges,
                                                                            double range_max, const Pose2& pose) const {
  Match m;
  const double reject2 = o_.reject_distance * o_.reject_distance;
  double kept_sum = 0.0;
  for (size_t i = 0; i < angles.size(); ++i) {
    const double expected = map_->CastOpenEdge(pose.translation(), pose.theta + angles[i], range_max);
    const double diff = ranges[i] - std::min(expected, range_max);
    const double d2 = diff * diff;
    if (d2 <= reject2) {
      kept_sum += d2;
      ++m.kept;
      m.cost += d2;
    } else {
      m.cost += reject2;
    }
  }
  m.cost /= std::max<size_t>(1, angles.size());
  m.rms = m.kept > 0 ? std::sqrt(kept_sum / m.kept) : o_.reject_distance;
  return m;
}

bool OdometricCalibrationLocalizer::AddScan(const ScanReading& scan) {
  if (!ScanHeaderIsUsable(scan)) return false;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!have_odom_ || scan.stamp - last_check_ < o_.period) return false;
  // State 1: no matching in sharp turns.
  if (std::abs(odom_history_.TurnRate(0.2)) * o_.wheel_base > o_.turn_threshold) return false;
  std::vector<double> angles, ranges;
  for (const ScanBeam& b : SampleBeams(scan, o_.beams)) {
    angles.push_back(b.angle);
    ranges.push_back(b.hit ? b.range : scan.range_max);  // a no-return matches an open virtual ray
  }
  if (static_cast<int>(angles.size()) < o_.min_rays) return false;
  last_check_ = scan.stamp;
  // State 2: the stored scan against the virtual scan at the estimate of its own time.
  const Pose2 odom_at_scan = odom_history_.At(scan.stamp);
  const Pose2 estimate = map_from_odom_ * odom_at_scan;
  const Match here = Compare(angles, ranges, scan.range_max, estimate);
  quality_ = (static_cast<double>(here.kept) / angles.size()) * std::exp(-here.rms * here.rms / (2 * 0.05 * 0.05));
  if (here.kept >= o_.min_rays && here.rms < o_.error_threshold) return true;
  // State 3: coarse-to-fine grid search of the region around that estimate.
  ++searches_;
  Pose2 best = estimate;
  Match best_match = here;
  double step_x = o_.search_x / 6, step_y = o_.search_y / 6, step_t = o_.search_theta / 8;
  int half_xy = 3, half_t = 4;
  for (int level = 0; level <= o_.refinements; ++level) {
    const Pose2 centre = best;
    for (int i = -half_xy; i <= half_xy; ++i) {
      for (int j = -half_xy; j <= half_xy; ++j) {
        for (int k = -half_t; k <= half_t; ++k) {
          if (i == 0 && j == 0 && k == 0) continue;
          const Pose2 candidate{centre.x + i * step_x, centre.y + j * step_y,
                                NormalizeAngle(centre.theta + k * step_t)};
          const Match m = Compare(angles, ranges, scan.range_max, candidate);
          if (m.cost < best_match.cost) {
            best_match = m;
            best = candidate;
          }
        }
      }
    }
    step_x /= 3;
    step_y /= 3;
    step_t /= 3;
    half_xy = half_t = 2;
  }
  if (best_match.kept < o_.min_rays || !(best_match.cost < here.cost)) return true;
  // Carried to now by the odometry since the scan: map_from_odom moves, the odometry does not.
  map_from_odom_ = best * odom_at_scan.inverse();
  const double sxy = 3 * step_x, st = 3 * step_t;  // the finest grid step searched
  anchor_covariance_ = Eigen::Vector3d(sxy * sxy + best_match.rms * best_match.rms / best_match.kept,
                                       sxy * sxy + best_match.rms * best_match.rms / best_match.kept, st * st)
                           .asDiagonal();
  anchor_distance_ = distance_;
  quality_ = (static_cast<double>(best_match.kept) / angles.size()) *
             std::exp(-best_match.rms * best_match.rms / (2 * 0.05 * 0.05));
  return true;
}

PoseEstimate OdometricCalibrationLocalizer::Estimate() const {
  std::lock_guard<std::mutex> lock(mutex_);
  PoseEstimate e;
  if (!have_odom_) return e;
  e.valid = true;
  e.stamp = odom_history_.latest().stamp;
  e.pose = map_from_odom_ * odom_history_.latest().pose;
  const double driven = distance_ - anchor_distance_;
  e.covariance = anchor_covariance_;
  e.covariance.diagonal() += Eigen::Vector3d(kVariancePerMetreXY, kVariancePerMetreXY, kVariancePerMetreTheta) * driven;
  e.quality = quality_;
  return e;
}

MethodContext OdometricCalibrationLocalizer::Suitability(bool laser_fresh) const {
  return {name(), laser_fresh ? 1.0 : 0.0, {3.0, 3.0, 1.0 + 4.0 * std::clamp(Estimate().quality, 0.0, 1.0)}};
}

int OdometricCalibrationLocalizer::searches() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return searches_;
}

}  // namespace navd::localization
