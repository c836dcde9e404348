#pragma once
// navd-replay --mode slam: graph SLAM (services/mapping/graph_slam.h) over a log's scans with the
// odometry given per scan, judged against the log's corrected poses.
#include <cstddef>
#include <string>
#include <vector>

#include "services/common/carmen_log.h"
#include "services/common/odometry_noise.h"
#include "services/common/pose2.h"
#include "services/mapping/graph_slam.h"

namespace navd::replay {

struct SlamRunOptions {
  double front_recovery = 0.0;       // the front end's FrontEndRecoveryOptions::below_score (0: off)
  bool learn_odometry_bias = false;  // GraphSlamOptions::odometry_bias on
  double frame_turn = 0.0;           // rad the map frame is turned by at the first pose
  bool drop_seen_through = false;    // GraphSlamOptions::drop_seen_through
  size_t return_budget = mapping::GraphSlamOptions{}.return_budget;
  OdometryNoise odometry;  // the odometry's noise, which the front end's window allows for

  std::string out;           // TUM trajectory of every scan, in file order (the final, optimised poses)
  std::string map_out;       // the map SLAM draws as map_server YAML + PGM ("": none)
  std::string png;           // ... and as a PNG for people ("": none)
  std::string graph_out;     // the optimised pose graph in g2o's format ("": none)
  double resolution = 0.05;  // m per cell of map_out and png
};

// Graph SLAM over the log's scans with the given odometry (one pose per scan, its own frame); the
// map frame starts at the log's first pose. Prints the ATE against the log's corrected poses after
// SE(2) alignment, each accepted loop closure and refinement match judged against the corrected
// relative pose, the time per scan and the scan consistency of the estimate and of the log's
// poses. Returns the exit code.
int Slam(const CarmenLog& log, const std::vector<Pose2>& odometry, const SlamRunOptions& options);

}  // namespace navd::replay
