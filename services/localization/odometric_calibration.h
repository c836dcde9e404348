#pragma once
// Seed 000's odometric calibration (Wahde et al., section 4.3): odometry carries the pose, and a
// few times per second a laser scan checks it against a virtual scan taken in the map.
//  State 1: while the wheels' speeds differ by more than T_dv (a sharp turn) no check is made.
//  State 2: the stored scan is compared ray by ray with the virtual scan at the estimated pose of
//           its own time; rays that differ by more than T_mo are ignored (moving obstacles, not
//           pose error); if the RMS of the rest is under T_eps the pose stands.
//  State 3: otherwise the pose is searched in an L_x x L_y x L_phi region around that estimate,
//           and the best pose at the scan's time is carried to now with the odometry since, which
//           is good for changes even when it is not for absolute poses.
// The seed defers the matcher's details to Sandberg et al. (2009) and gives no values; the
// defaults below are our choices, documented: T_mo is the seed's moving-obstacle threshold, the
// search is a coarse-to-fine grid, and a ray beyond T_mo costs T_mo^2 during the search (so a pose
// cannot win by explaining fewer rays). Metres, radians, seconds, map frame.
#include <memory>
#include <mutex>

#include "services/common/occupancy_grid.h"
#include "services/common/ray_caster.h"
#include "services/localization/localizer.h"
#include "services/localization/odometry_history.h"

namespace navd::localization {

struct OdometricCalibrationOptions {
  double period = 0.2;             // s between checks ("at least a few times per second")
  double wheel_base = 0.33;        // m, to turn the odometry's turn rate into |v_L - v_R|
  double turn_threshold = 0.1;     // T_dv, m/s of wheel speed difference
  double reject_distance = 0.30;   // T_mo, m
  double error_threshold = 0.015;  // T_eps, m (RMS)
  double search_x = 0.5;           // L_x, m (full width, centred on the estimate)
  double search_y = 0.5;           // L_y, m
  double search_theta = 0.4;       // L_phi, rad
  int refinements = 4;             // grid levels after the first, each a third of the last's step
  int beams = 60;                  // rays compared per scan, evenly spread
  int min_rays = 15;               // fewer usable rays: no check
};

class OdometricCalibrationLocalizer : public Localizer {
 public:
  OdometricCalibrationLocalizer(const OccupancyGrid& map, const OdometricCalibrationOptions& options = {},
                                const Pose2& initial_pose = {});
  std::string name() const override { return "calibration"; }
  void AddOdometry(const OdometryReading& reading) override;
  // Returns true when the scan was checked (whether or not the pose moved).
  bool AddScan(const ScanReading& scan) override;
  PoseEstimate Estimate() const override;
  // Takes its virtual scans in `map` from now on; the calibration is kept.
  bool SetMap(const OccupancyGrid& map) override;
  // Needs the laser to calibrate; a few milliseconds per search, recovers from errors within its
  // search region, as precise as its matches.
  MethodContext Suitability(bool laser_fresh) const override;
  // Searches (State 3) run so far, for tests and telemetry.
  int searches() const;

 private:
  void ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) override;
  struct Match {
    double cost = 0.0;  // mean of min(diff^2, T_mo^2) over the rays
    double rms = 0.0;   // RMS of the rays within T_mo
    int kept = 0;
  };
  Match Compare(const std::vector<double>& angles, const std::vector<double>& ranges, double range_max,
                const Pose2& pose) const;

  const OdometricCalibrationOptions o_;
  mutable std::mutex mutex_;
  std::shared_ptr<const RayCaster> map_;  // the virtual scans' map; guarded by mutex_
  OdometryHistory odom_history_;
  bool have_odom_ = false;
  Pose2 initial_pose_;
  Pose2 map_from_odom_;
  Eigen::Matrix3d anchor_covariance_ = Eigen::Matrix3d::Zero();
  double anchor_distance_ = 0.0;  // odometry distance at the last anchoring
  double distance_ = 0.0;         // odometry distance so far
  double last_check_ = -1e18;
  double quality_ = 1.0;
  int searches_ = 0;
};

}  // namespace navd::localization
