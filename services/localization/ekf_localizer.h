#pragma once
// The extended Kalman filter of seed 002 §2.1 (Lazea et al.): the state is the robot's map pose
// x = (x, y, theta); odometry gives the input u and the prediction
//   x+ = x + dD cos(theta + dtheta/2),  y+ = y + dD sin(theta + dtheta/2),  theta+ = theta + dtheta,
//   P+ = A_x P A_x^T + A_u U A_u^T + Q
// (written here as the composition with the odometry's robot-frame increment, which is that model
// for a differential drive's arc and also holds for other reference points and drives);
// the correction is a scan-to-map match: the scan is fitted to the map (Gauss-Newton on the
// likelihood field) from the predicted pose, and the fitted pose is the measurement, h(x) = x,
// H = I, with the fit's covariance as R. Matches whose innovation fails a chi-square gate are
// refused, so a scan full of people cannot drag the estimate, unless the refusals persist (then the
// filter re-anchors at the match). The seed leaves U, Q and R open; the
// defaults below are documented choices. Metres, radians, map frame.
#include <Eigen/Core>
#include <memory>
#include <mutex>

#include "services/common/occupancy_grid.h"
#include "services/localization/likelihood_field.h"
#include "services/localization/localizer.h"
#include "services/localization/odometry_history.h"
#include "services/localization/scan_to_map_fit.h"

namespace navd::localization {

struct EkfOptions {
  // Input noise U: along and across the motion sigma = k_distance |dD|; sigma(dtheta) =
  // k_turn |dtheta| + k_turn_per_metre |dD|.
  double k_distance = 0.05;
  double k_turn = 0.05;
  double k_turn_per_metre = 0.035;  // rad/m (2 degrees per metre)
  // Process noise Q per metre driven (slip the wheels do not report), variances.
  double q_xy_per_metre = 1e-4;     // m^2/m
  double q_theta_per_metre = 1e-4;  // rad^2/m
  // Correct only after the robot moved this much since the last correction (as AMCL): repeated
  // matches of one standing scene are one measurement, not many.
  double update_min_distance = 0.05;  // m
  double update_min_angle = 0.05;     // rad
  double gate = 16.27;                // chi-square, 3 degrees of freedom, 0.999
  // After this many matches in a row refused by the gate, the filter is the one that is wrong (a
  // first match caught in a local minimum leaves it confident and off by centimetres, and every
  // right match after looks like an outlier): it re-anchors at the latest match.
  int reanchor_after = 5;
  int beams = 120;  // beams used per scan, evenly spread
  LikelihoodFieldOptions field;
  ScanToMapFitOptions fit;
};

class EkfLocalizer : public Localizer {
 public:
  // Until SetPose, the robot is taken to stand at `initial_pose` with `initial_covariance`.
  EkfLocalizer(const OccupancyGrid& map, const EkfOptions& options = {}, const Pose2& initial_pose = {},
               const Eigen::Matrix3d& initial_covariance = Eigen::Matrix3d::Identity() * 0.01);
  std::string name() const override { return "ekf"; }
  void AddOdometry(const OdometryReading& reading) override;
  bool AddScan(const ScanReading& scan) override;
  PoseEstimate Estimate() const override;
  // Matches scans against `map` from now on; the belief is kept.
  bool SetMap(const OccupancyGrid& map) override;
  // Needs the laser to correct; cheap (one fit per scan), tracks but cannot recover from a wrong
  // pose outside its gate, as precise as its matches.
  MethodContext Suitability(bool laser_fresh) const override;
  // Matches refused by the gate since the last accepted one.
  int rejected_in_a_row() const;

 private:
  void ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) override;
  struct Belief {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();  // (x, y, theta), map frame
    Eigen::Matrix3d p = Eigen::Matrix3d::Identity();
  };
  // The belief moved by the robot-frame odometry increment d.
  Belief Predicted(const Belief& b, const Pose2& d) const;

  const EkfOptions o_;
  // The map's likelihood field and the scan matcher on it; SetMap replaces both.
  struct MapModel {
    MapModel(const OccupancyGrid& map, const EkfOptions& o) : field(map, o.field), fit(field, o.fit) {
      field.PrepareSurfaceDistance();  // with the rest of the model, off the filter's first scan
    }
    LikelihoodField field;
    ScanToMapFit fit;
  };
  mutable std::mutex mutex_;
  std::shared_ptr<const MapModel> model_;  // guarded by mutex_
  Belief belief_;                          // at the odometry predicted_at_odom_
  Pose2 predicted_at_odom_;
  OdometryHistory odom_history_;
  bool have_odom_ = false;
  Pose2 latest_odom_;
  Pose2 corrected_at_odom_;  // odometry at the last correction
  bool moved_since_correction_ = true;
  int rejected_in_a_row_ = 0;
  double quality_ = 1.0;
  double stamp_ = 0.0;
};

}  // namespace navd::localization
