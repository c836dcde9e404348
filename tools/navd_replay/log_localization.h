#pragma once
// navd-replay --mode localize: a localiser (the particle filter, the EKF with scan-to-map matching,
// or the odometric calibration) over a log's scans on a map, judged against the log's corrected
// poses.
#include <cstdint>
#include <string>
#include <vector>

#include "services/common/carmen_log.h"
#include "services/common/occupancy_grid.h"
#include "services/common/odometry_noise.h"
#include "services/common/pose2.h"

namespace navd::replay {

// The particle filter's settings a run may change: its odometry noise (AMCL's alphas), the motion
// between the scans it weighs (AMCL's update_min_d, update_min_a; 0: the filter's defaults) and the
// particles it keeps once gathered. The estimate is their mean, as steady as they are many: on the
// real logs 2000 track 1-4 mm closer than navd's 500 (for navsim's robots, whose odometry arrives
// every few centimetres), at about a millisecond more per scan.
struct FilterTuning {
  double motion_noise = 0.0;             // AMCL's alpha1..4 (variance per unit of motion squared)
  double heading_per_metre_noise = 0.0;  // AMCL's alpha2 (rad² per m² driven) at least this
  double update_min_d = 0.0;             // m
  double update_min_a = 0.0;             // rad
  int min_particles = 2000;
};

struct LocalizationRunOptions {
  std::string method = "amcl";  // amcl (the particle filter), ekf or calibration
  OdometryNoise noise;          // the replay's odometry noise, which the EKF is told
  uint64_t seed = 1;            // the particle filter's
  FilterTuning filter;
  std::string out;  // TUM trajectory, one line per scan in file order (map frame)
};

// Starts at the log's first pose and takes the odometry given per scan (one pose per scan, in the
// odometry's own frame); prints the position and heading RMSE against the log's poses, and the
// position RMSE after SE(2) alignment. Returns the exit code.
int Localize(const CarmenLog& log, const std::vector<Pose2>& odometry, const OccupancyGrid& map,
             const LocalizationRunOptions& options);

}  // namespace navd::replay
