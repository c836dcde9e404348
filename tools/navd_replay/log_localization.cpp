#include "tools/navd_replay/log_localization.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "services/common/scan_reach.h"
#include "services/common/text_file.h"
#include "services/common/trajectory_alignment.h"
#include "services/common/tum_trajectory.h"
#include "services/localization/ekf_localizer.h"
#include "services/localization/odometric_calibration.h"
#include "services/localization/particle_filter.h"

namespace navd::replay {
namespace {

using localization::Localizer;
using localization::ScanReading;

// m: the longest reading the localiser judges. Further, a reading's end is rarely on a mapped
// wall (the map is drawn to 15 m from each pose) and a heading error of a milliradian moves it
// more than a map cell; a scan with too little that near (an open hall) is judged to the far reach,
// as the map drew it (ScanReach).
constexpr ScanReachOptions kLocalizationReach{25.0, 50.0};

std::unique_ptr<Localizer> MakeLocalizer(const OccupancyGrid& map, const LocalizationRunOptions& options) {
  using namespace localization;
  if (options.method == "calibration") {
    OdometricCalibrationOptions o;
    o.turn_threshold = 1e9;  // the log's scans are seconds apart: no turn rate to gate on
    return std::make_unique<OdometricCalibrationLocalizer>(map, o);
  }
  if (options.method == "ekf") {
    // The filter's input noise is the replay's odometry noise model.
    EkfOptions o;
    o.k_distance = options.noise.translation;
    o.k_turn = options.noise.translation;
    o.k_turn_per_metre = options.noise.rotation_per_metre;
    o.field.range_max = 20.0;
    return std::make_unique<EkfLocalizer>(map, o);
  }
  ParticleFilterOptions o;
  o.seed = options.seed;
  o.range_max = 20.0;  // the z_rand density of a long-range (SICK) scanner's useful range
  o.alpha1 = o.alpha2 = o.alpha3 = o.alpha4 = options.filter.motion_noise;
  o.alpha2 = std::max(o.alpha2, options.filter.heading_per_metre_noise);
  if (options.filter.update_min_d > 0.0) o.update_min_distance = options.filter.update_min_d;
  if (options.filter.update_min_a > 0.0) o.update_min_angle = options.filter.update_min_a;
  o.min_particles = options.filter.min_particles;
  o.max_particles = std::max(o.max_particles, o.min_particles);
  return std::make_unique<ParticleFilterLocalizer>(map, o);
}

}  // namespace

int Localize(const CarmenLog& log, const std::vector<Pose2>& odometry, const OccupancyGrid& map,
             const LocalizationRunOptions& options) {
  const std::unique_ptr<Localizer> localizer = MakeLocalizer(map, options);
  localizer->AddOdometry({odometry.front(), Eigen::Matrix3d::Zero(), log.scans.front().timestamp});
  localizer->SetPose(log.scans.front().pose, Eigen::Matrix3d::Zero());
  std::string tum;
  double sq_pos = 0.0, sq_head = 0.0, worst = 0.0;
  std::vector<Pose2> estimate, truth;
  for (size_t k = 0; k < log.scans.size(); ++k) {
    const CarmenScan& s = log.scans[k];
    if (k > 0) localizer->AddOdometry({odometry[k], Eigen::Matrix3d::Zero(), s.timestamp});
    ScanReading scan;
    scan.ranges = s.ranges;
    scan.angle_min = s.angle_min;
    scan.angle_increment = s.angle_increment;
    scan.range_min = 0.05;
    // Beams are judged further than the map was drawn (its usable range): a corridor's far end,
    // mapped when the robot was nearer, is what holds the position along the corridor.
    scan.range_max = std::min(s.no_return_range(), ScanReach(s.ranges, s.no_return_range(), kLocalizationReach));
    scan.stamp = s.timestamp;
    localizer->AddScan(scan);
    const Pose2 e = localizer->Estimate().pose;
    estimate.push_back(e);
    truth.push_back(s.pose);
    const double ep = std::hypot(e.x - s.pose.x, e.y - s.pose.y), eh = std::abs(NormalizeAngle(e.theta - s.pose.theta));
    sq_pos += ep * ep;
    sq_head += eh * eh;
    worst = std::max(worst, ep);
    tum += FormatTumLine(s.timestamp, e);
    if ((k + 1) % 100 == 0 || k + 1 == log.scans.size())
      std::fprintf(stderr, "\r  localised %zu/%zu scans", k + 1, log.scans.size());
  }
  std::fprintf(stderr, "\n");
  WriteFileAtomically(options.out, tum);
  const double n_scans = static_cast<double>(log.scans.size());
  std::printf("localize (%s): %zu scans, position RMSE %.4f m, heading RMSE %.4f rad, worst %.3f m%s -> %s\n",
              options.method.c_str(), log.scans.size(), std::sqrt(sq_pos / n_scans), std::sqrt(sq_head / n_scans),
              worst, worst > 0.5 ? " (lost at times)" : ", never lost", options.out.c_str());
  // A map drawn in a frame of its own (a SLAM run's, which starts where its localiser put the
  // first scan) is judged by its shape: the trajectory on it aligned to the corrected poses.
  std::printf("localize: RMSE %.4f m after SE(2) alignment\n", AlignedTrajectoryError(estimate, truth).position_rmse);
  return 0;
}

}  // namespace navd::replay
