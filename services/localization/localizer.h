#pragma once
// The interface of pose estimators: they consume odometry and laser scans and report the robot's
// pose in the map frame with a covariance. Units: metres, radians, seconds.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "services/common/occupancy_grid.h"
#include "services/common/pose2.h"
#include "services/localization/method_arbiter.h"

namespace navd::localization {

// An odometry reading: the robot's pose in the odom frame (which drifts) and its covariance.
struct OdometryReading {
  Pose2 pose;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double stamp = 0.0;
};

// A planar laser scan in the robot frame (the scanner sits at the robot's centre, facing forward):
// beam i points at angle_min + i * angle_increment; a reading at or beyond range_max (or +inf) is
// a no-return, and one under range_min or services/common/scan_reach.h's kMinEchoRange, NaN or
// -inf says nothing.
struct ScanReading {
  std::vector<float> ranges;
  double angle_min = 0.0;
  double angle_increment = 0.0;
  double range_min = 0.0;
  double range_max = 0.0;
  double stamp = 0.0;
};

struct PoseEstimate {
  Pose2 pose;                                            // map frame
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // (x, y, theta)
  double stamp = 0.0;
  bool valid = false;  // false until the first reading
  // How well the sensors agree with the map, 0 (lost) to 1; 1 for pure odometry, which cannot tell.
  double quality = 1.0;
  // Times the localiser moved its estimate on its own to where the scans fit decisively better
  // than where it was: a pose lost (carried off, left behind) and found again.
  uint64_t relocations = 0;
  // m: how widely the position is spread, sqrt(var x + var y).
  double PositionSpread() const { return std::sqrt(std::max(0.0, covariance(0, 0) + covariance(1, 1))); }
};

class Localizer {
 public:
  virtual ~Localizer() = default;
  virtual std::string name() const = 0;
  virtual void AddOdometry(const OdometryReading& reading) = 0;
  // Scans correct the estimate in localisers that use them; others ignore them. Returns whether
  // the scan was used (malformed scans are rejected, never applied).
  virtual bool AddScan(const ScanReading& scan) { return false; }
  // Re-anchors the estimate at `pose` (map frame) with `covariance` of (x, y, theta). Throws
  // navd::Error(kInvalidArgument) naming the field for non-finite values or a covariance that is
  // not symmetric with a non-negative diagonal.
  void SetPose(const Pose2& pose, const Eigen::Matrix3d& covariance);
  virtual PoseEstimate Estimate() const = 0;
  // Forgets the pose and searches the whole map for it (seed 000's "wake-up"). Returns false for
  // localisers that cannot.
  virtual bool GlobalRelocalize() { return false; }
  // Forgets the pose and searches for it around `pose` (map frame) with `covariance` of (x, y,
  // theta): the wake-up's first search, near where the robot was lost. Returns false for
  // localisers that cannot search (they keep their estimate) and for non-finite input.
  virtual bool SearchAround(const Pose2& pose, const Eigen::Matrix3d& covariance);
  // The wake-up's whole-map search run beside the estimate, not in its place: the estimate goes on
  // tracking (a pose lost where the map does not explain the scans, among people or furniture, is
  // often still right, and a whole-map search in a building of like rooms can settle in the wrong
  // one) while another localiser of the same kind searches the whole map. SearchEstimate says what
  // it has found so far (valid = false while none runs); EndSearch stops it, and with `adopt` moves
  // the estimate to the search's. Returns false for localisers that cannot (GlobalRelocalize then
  // searches in place); a new search, SetPose and GlobalRelocalize end a running one. SearchAround
  // re-anchors the estimate only and leaves a search beside running: the wake-up searches near
  // where the robot was lost while the whole-map search, begun at the first poorly fitting scan,
  // goes on.
  virtual bool StartSearch() { return false; }
  virtual PoseEstimate SearchEstimate() const { return {}; }
  virtual void EndSearch(bool adopt) {}
  // A new localiser of the same kind on the same map and options, without a pose: what
  // StartSearch runs beside this one. nullptr for kinds that cannot search the whole map.
  virtual std::unique_ptr<Localizer> Fresh() const { return nullptr; }
  // Matches scans against `map` from now on (the same map frame: the pose is kept), e.g. once a
  // map has been built or loaded. Thread-safe; the costly part (likelihood fields, ray casters) is
  // built outside the localiser's lock, so scans go on being matched against the old map meanwhile.
  // Returns whether this localiser uses a map at all.
  virtual bool SetMap(const OccupancyGrid& map) { return false; }
  // How suitable this method is now, for the chapter-10 arbiter: the gate (can it work with the
  // sensors there are) and the criteria computing time, fault tolerance and precision, 1..5.
  virtual MethodContext Suitability(bool laser_fresh) const = 0;

 protected:
  // Called by SetPose with checked values; theta already in (-pi, pi].
  virtual void ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) = 0;
  // Called by SearchAround with checked values: re-anchoring to search, which a localiser may tell
  // from a pose it is told (what it knows of how the pose was lost can still help). ResetPose here.
  virtual void ResetForSearch(const Pose2& pose, const Eigen::Matrix3d& covariance) { ResetPose(pose, covariance); }
  // Whether SearchAround re-anchors this localiser at the search's cloud: those that hold many
  // hypotheses (a Gaussian estimate re-anchored at the cloud's mean would just forget its own).
  virtual bool CanSearch() const { return false; }
};

}  // namespace navd::localization
