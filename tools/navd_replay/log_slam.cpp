#include "tools/navd_replay/log_slam.h"

#include <Eigen/Eigenvalues>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <future>
#include <utility>

#include "services/common/map_server_format.h"
#include "services/common/png_format.h"
#include "services/common/quantile.h"
#include "services/common/relative_pose_error.h"
#include "services/common/text_file.h"
#include "services/common/trajectory_alignment.h"
#include "services/common/tum_trajectory.h"
#include "services/mapping/occupancy_grid_mapper.h"
#include "services/mapping/pose_graph_g2o.h"
#include "services/mapping/scan_consistency.h"
#include "tools/navd_replay/log_consistency.h"
#include "tools/navd_replay/log_map.h"

namespace navd::replay {
namespace {

// How far a closure is off the corrected poses, in the directions it measures: a partial
// refinement match (a corridor driven the other way) holds its node across the corridor only, and
// along it, where its edge's sigma exceeds 0.1 m, carries where the graph put the node, as loosely
// as the odometry would. Its translation (m) in those directions and in all, and its turn (rad).
struct ClosureOffset {
  double measured = 0.0, distance = 0.0, theta = 0.0;
};

ClosureOffset OffsetFromTruth(const mapping::LoopClosure& c, const std::vector<Pose2>& truth) {
  const Pose2 true_relative = truth[c.from_scan].inverse() * truth[c.to_scan];
  const Pose2 diff = true_relative.inverse() * c.measurement;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> xy(c.information.topLeftCorner<2, 2>());
  Point2 measured = Point2::Zero();
  for (int k = 0; k < 2; ++k)
    if (xy.eigenvalues()(k) >= 1.0 / (0.1 * 0.1))
      measured += xy.eigenvectors().col(k) * xy.eigenvectors().col(k).dot(Point2(diff.x, diff.y));
  return {measured.norm(), std::hypot(diff.x, diff.y), diff.theta};
}

// A closure is wrong when it is more than 0.3 m or 0.1 rad off the corrected poses.
int CountWrong(const std::vector<mapping::LoopClosure>& closures, const std::vector<Pose2>& truth, const char* kind) {
  int wrong = 0;
  for (const auto& c : closures) {
    const ClosureOffset off = OffsetFromTruth(c, truth);
    if (off.measured > 0.3 || std::abs(off.theta) > 0.1) {
      ++wrong;
      std::fprintf(stderr, "wrong %s: scan %d to scan %d (score %.3f) is %.3f m, %.3f rad off the corrected poses\n",
                   kind, c.from_scan, c.to_scan, c.score, off.distance, off.theta);
    }
  }
  return wrong;
}

// How far the loop closures, each a match of one scan against the scans of another pass, lie from
// the corrected poses: where scans and poses agree (a log rendered at its poses) a few
// millimetres in the median; beyond that, the scans place each other elsewhere than the poses do.
void PrintClosureOffsets(const std::vector<mapping::LoopClosure>& closures, const std::vector<Pose2>& truth) {
  if (closures.empty()) return;
  std::vector<double> offsets;
  offsets.reserve(closures.size());
  for (const auto& c : closures) offsets.push_back(OffsetFromTruth(c, truth).distance);
  std::printf("loop closures off the corrected poses: median %.3f m, 90th percentile %.3f m, worst %.3f m\n",
              Quantile(offsets, 0.5), Quantile(offsets, 0.9), Quantile(offsets, 1.0));
}

// How well the log's scans agree at SLAM's estimate and at the log's own poses (ScanConsistency).
// The two are independent and, on a dense log, each takes as long as SLAM did: the log's poses are
// scored on a second thread.
void PrintScanConsistency(const CarmenLog& log, const std::vector<Pose2>& estimate, const std::vector<Pose2>& truth) {
  std::vector<std::vector<Point2>> returns = ConsistencyReturns(log);
  std::future<double> at_log = std::async(std::launch::async, [&truth, copy = returns]() mutable {
    return mapping::ScanConsistency(truth, std::move(copy)).Score().mean_distance;
  });
  const double at_estimate = mapping::ScanConsistency(estimate, std::move(returns)).Score().mean_distance;
  std::printf(
      "scan consistency: returns %.1f mm from the lines the other scans draw at the estimate, %.1f mm at the "
      "log's poses\n",
      1e3 * at_estimate, 1e3 * at_log.get());
}

// The map SLAM draws at its final poses, as options.map_out and options.png ask.
void WriteMap(const mapping::GraphSlam& slam, const SlamRunOptions& options) {
  mapping::MapperOptions o;
  o.resolution = options.resolution;
  const OccupancyGrid grid = slam.RenderMap(o);
  NoteCoarserMap(grid, options.resolution);
  if (!options.map_out.empty()) SaveMapServerMap(grid, options.map_out);
  if (!options.png.empty()) SaveMapPng(grid, options.png);
  std::printf("map: %dx%d cells at %.3f m%s%s%s%s\n", grid.width(), grid.height(), grid.resolution(),
              options.map_out.empty() ? "" : " -> ", options.map_out.c_str(), options.png.empty() ? "" : " -> ",
              options.png.c_str());
}

}  // namespace

int Slam(const CarmenLog& log, const std::vector<Pose2>& odometry, const SlamRunOptions& options) {
  // The map frame starts at the log's first pose, so the map lines up with the log's own (turned
  // by frame_turn: the correlative grids' axes lie along the map frame's, so a turned frame
  // shows how much a result owes to where those axes fall).
  mapping::GraphSlamOptions slam_options;
  slam_options.first_pose = log.scans.front().pose;
  slam_options.first_pose.theta = NormalizeAngle(slam_options.first_pose.theta + options.frame_turn);
  slam_options.front_recovery.below_score = options.front_recovery;
  if (options.learn_odometry_bias) slam_options.odometry_bias = mapping::RobotOdometryBias();
  slam_options.drop_seen_through = options.drop_seen_through;
  slam_options.return_budget = options.return_budget;
  slam_options.odometry = options.odometry;
  mapping::GraphSlam slam(slam_options);
  double busy = 0.0;
  for (size_t k = 0; k < log.scans.size(); ++k) {
    const CarmenScan& s = log.scans[k];
    const Pose2& odom = odometry[k];
    mapping::RangeScan scan{s.ranges, s.angle_min, s.angle_increment, s.timestamp};
    scan.range_max = s.no_return_range();
    const auto t0 = std::chrono::steady_clock::now();
    slam.AddScan(odom, scan);
    busy += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if ((k + 1) % 50 == 0 || k + 1 == log.scans.size())
      std::fprintf(stderr, "\r  slam %zu/%zu scans, %d loop closures", k + 1, log.scans.size(), slam.loop_closures());
  }
  {
    const auto t0 = std::chrono::steady_clock::now();
    slam.Refine();
    busy += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  std::fprintf(stderr, "\n");
  const std::vector<Pose2> estimate = slam.Trajectory();
  const std::vector<Pose2> truth = LogPoses(log);
  const TrajectoryError error = AlignedTrajectoryError(estimate, truth);
  // Step by step, as Kümmerle et al.'s relations metric (Cartographer's paper reports it); a log of
  // one scan has no step (nan).
  RelativeError relative;
  relative.translation_mean = relative.rotation_mean = relative.along_rmse = relative.across_rmse = std::nan("");
  if (estimate.size() > 1) relative = RelativePoseError(estimate, truth);
  std::string tum;
  for (size_t k = 0; k < estimate.size(); ++k) tum += FormatTumLine(log.scans[k].timestamp, estimate[k]);
  WriteFileAtomically(options.out, tum);
  const int wrong = CountWrong(slam.closures(), truth, "loop closure");
  const int wrong_refinements = CountWrong(slam.refinements(), truth, "refinement match");
  std::printf(
      "slam: %zu scans, %d nodes, %d loop closures (%d wrong) of %d attempts, %zu refinement matches (%d wrong), "
      "ATE RMSE %.4f m after SE(2) alignment, heading RMSE %.4f rad, worst %.3f m, %.2f ms per scan, "
      "relative error per scan step %.4f m, %.4f rad (mean; RMS along the travel %.4f m, across it %.4f m), "
      "ATE %.4f m after Sim(2) alignment at scale %.5f -> %s\n",
      estimate.size(), slam.nodes(), slam.loop_closures(), wrong, slam.loop_attempts(), slam.refinements().size(),
      wrong_refinements, error.position_rmse, error.heading_rmse, error.worst,
      1e3 * busy / static_cast<double>(estimate.size()), relative.translation_mean, relative.rotation_mean,
      relative.along_rmse, relative.across_rmse, error.similarity_rmse, error.scale, options.out.c_str());
  PrintClosureOffsets(slam.closures(), truth);
  PrintScanConsistency(log, estimate, truth);
  if (options.learn_odometry_bias)
    std::printf("odometry bias learnt: scale %.4f, drift %.4f rad/m, turn error %.4f\n", slam.odometry_bias().scale(),
                slam.odometry_bias().drift(), slam.odometry_bias().turn_error());
  if (!options.graph_out.empty()) {
    WriteFileAtomically(options.graph_out, mapping::FormatG2o(slam.graph(), slam.node_scan_indices()));
    std::printf("pose graph: %d nodes (ids: their scans), %zu edges -> %s\n", slam.nodes(), slam.graph().edges().size(),
                options.graph_out.c_str());
  }
  if (!options.map_out.empty() || !options.png.empty()) WriteMap(slam, options);
  return 0;
}

}  // namespace navd::replay
