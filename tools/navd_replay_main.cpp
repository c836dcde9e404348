// navd-replay: runs navd's library code over a recorded CARMEN log, as fast as it can.
//   navd-replay --log FILE[.gz] --mode map --out MAP.yaml [--resolution 0.05]
//   navd-replay --log FILE[.gz] --mode render --out RENDERED.log [--step M] [--turn RAD] [--range-noise M]
//               [--people N] [--fov DEG --beams N] [--seed N]
//   navd-replay --log FILE[.gz] --mode localize|slam --out EST.tum [--odometry noisy|log]
//               [--map MAP.yaml] [--odom-noise T,R[,S,D]] [--seed N] [--localizer amcl|ekf|calibration]
//               [--front-recovery SCORE] [--odometry-bias auto|on|off] [--frame-turn RAD]
//               [--drop-seen-through] [--return-budget N]
//   navd-replay --log FILE[.gz] --mode consistency --out SCANS.txt [--trajectory EST.tum] [--scan K]
// `map` builds an occupancy grid from the log's (corrected) laser poses and saves it as a ROS
// map_server YAML + PGM, atomically. `localize` runs a localiser (the particle filter, or the EKF
// with scan-to-map matching) on the log's scans with, by default,
// odometry made from the corrected poses and corrupted by the seeded noise model of
// services/common/odometry_noise.h (per step between scans: translation scaled by 1 + N(0, T);
// heading error N(0, R * distance) plus N(0, T * |turn|); with S and D also a systematic scale
// 1 + S and heading drift D * distance),
// writes one TUM line (t x y z qx qy qz qw) per scan and prints the error against the corrected
// poses (SLAM also its relative error per scan step, services/common/relative_pose_error.h).
// Without --map it first builds the map from those poses. `--odometry log` takes the odometry the
// log itself holds instead (carmen_odometry.h): how raw robot logs run; SLAM then searches again
// wider where a scan fits its predicted pose poorly (--front-recovery) and learns the odometry's
// systematic error (--odometry-bias, OdometryBias). SLAM's front end widens its
// window with the motion by --odom-noise's model, never less than the default one (with
// --odometry log: the robot's odometry's noise, as far as it is known). `render` writes a FLASER
// log whose scans are cast again in the map the log's poses draw (at --resolution), at those poses
// or every --step metres between them, with --people walking the log's path, by the log's scanner
// or another one (--fov, --beams) (services/mapping/log_renderer.h). `consistency` measures how
// well the scans agree with one another at the log's poses or a trajectory's, with no ground truth
// (services/mapping/scan_consistency.h); slam prints it for its estimate and the log's poses.
#include <CLI/CLI.hpp>
#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <utility>

#include "services/common/carmen_log.h"
#include "services/common/carmen_odometry.h"
#include "services/common/error.h"
#include "services/common/map_server_format.h"
#include "services/common/odometry_noise.h"
#include "services/common/png_format.h"
#include "services/common/scan_reach.h"
#include "services/common/text_file.h"
#include "services/common/world.h"
#include "services/localization/ekf_localizer.h"
#include "services/localization/odometric_calibration.h"
#include "services/localization/particle_filter.h"
#include "services/common/ray_caster.h"
#include "services/common/relative_pose_error.h"
#include "services/mapping/graph_slam.h"
#include "services/mapping/known_pose_map.h"
#include "services/mapping/log_renderer.h"
#include "services/mapping/occupancy_grid_mapper.h"
#include "services/mapping/odometry_pairing.h"
#include "services/mapping/pose_graph_g2o.h"
#include "services/mapping/scan_consistency.h"
#include "services/common/trajectory_alignment.h"

namespace {

struct SlamTuning {
  double front_recovery = 0.0;       // the front end's FrontEndRecoveryOptions::below_score (0: off)
  bool learn_odometry_bias = false;  // GraphSlamOptions::odometry_bias on
  double frame_turn = 0.0;           // rad the map frame is turned by at the first pose
  bool drop_seen_through = false;    // GraphSlamOptions::drop_seen_through
  size_t return_budget = navd::mapping::GraphSlamOptions{}.return_budget;
  navd::OdometryNoise odometry;  // the odometry's noise, which the front end's window allows for
};

// Says so when a map spread too wide for a grid at the resolution asked for was drawn coarser
// (ResolutionToFit).
void NoteCoarserMap(const navd::OccupancyGrid& grid, double resolution) {
  if (grid.resolution() > resolution + 1e-9)
    std::fprintf(stderr,
                 "navd-replay: the map spans %.0f x %.0f m: drawn at %.3f m, not %.3f, to stay within %lld cells\n",
                 grid.width() * grid.resolution(), grid.height() * grid.resolution(), grid.resolution(), resolution,
                 navd::OccupancyGrid::kMaxCells);
}

// m: the echoes the scan consistency measures, as far as the maps are drawn from each pose.
constexpr double kConsistencyReach = 15.0;

// The log's scans' echoes, one list per scan in file order, robot frame, as the scan consistency
// (services/mapping/scan_consistency.h) measures them.
std::vector<std::vector<navd::Point2>> ConsistencyReturns(const navd::CarmenLog& log) {
  std::vector<std::vector<navd::Point2>> returns;
  returns.reserve(log.scans.size());
  for (const navd::CarmenScan& s : log.scans)
    returns.push_back(
        navd::ScanReturns(s.ranges, s.angle_min, s.angle_increment, s.no_return_range(), kConsistencyReach));
  return returns;
}

std::vector<navd::Pose2> LogPoses(const navd::CarmenLog& log) {
  std::vector<navd::Pose2> poses;
  for (const navd::CarmenScan& s : log.scans) poses.push_back(s.pose);
  return poses;
}

// Graph SLAM over the log's scans with the given odometry (one pose per scan): the TUM trajectory of every scan (the
// final, optimised poses), judged against the log's corrected poses after SE(2) alignment; each
// accepted loop closure judged against the corrected relative pose.
int Slam(const navd::CarmenLog& log, const std::vector<navd::Pose2>& odometry, const SlamTuning& tuning,
         const std::string& out, const std::string& map_out, const std::string& graph_out, const std::string& png,
         double resolution) {
  using namespace navd;
  // The map frame starts at the log's first pose, so the map lines up with the log's own (turned
  // by frame_turn: the correlative grids' axes lie along the map frame's, so a turned frame
  // shows how much a result owes to where those axes fall).
  mapping::GraphSlamOptions options;
  options.first_pose = log.scans.front().pose;
  options.first_pose.theta = NormalizeAngle(options.first_pose.theta + tuning.frame_turn);
  options.front_recovery.below_score = tuning.front_recovery;
  if (tuning.learn_odometry_bias) options.odometry_bias = mapping::RobotOdometryBias();
  options.drop_seen_through = tuning.drop_seen_through;
  options.return_budget = tuning.return_budget;
  options.odometry = tuning.odometry;
  mapping::GraphSlam slam(options);
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
  for (size_t k = 0; k < estimate.size(); ++k) {
    const Pose2& e = estimate[k];
    char line[160];
    std::snprintf(line, sizeof line, "%.6f %.6f %.6f 0 0 0 %.9f %.9f\n", log.scans[k].timestamp, e.x, e.y,
                  std::sin(e.theta / 2), std::cos(e.theta / 2));
    tum += line;
  }
  WriteFileAtomically(out, tum);
  // A closure is wrong when it disagrees with the corrected poses by more than 0.3 m or 0.1 rad, in
  // the directions it measures: a partial refinement match (a corridor driven the other way) holds
  // its node across the corridor only, and along it, where its edge's sigma exceeds 0.1 m, carries
  // where the graph put the node, as loosely as the odometry would.
  auto count_wrong = [&](const std::vector<mapping::LoopClosure>& closures, const char* kind) {
    int wrong = 0;
    for (const auto& c : closures) {
      const Pose2 true_relative = truth[c.from_scan].inverse() * truth[c.to_scan];
      const Pose2 diff = true_relative.inverse() * c.measurement;
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> xy(c.information.topLeftCorner<2, 2>());
      Point2 measured = Point2::Zero();
      for (int k = 0; k < 2; ++k)
        if (xy.eigenvalues()(k) >= 1.0 / (0.1 * 0.1))
          measured += xy.eigenvectors().col(k) * xy.eigenvectors().col(k).dot(Point2(diff.x, diff.y));
      if (measured.norm() > 0.3 || std::abs(diff.theta) > 0.1) {
        ++wrong;
        std::fprintf(stderr, "wrong %s: scan %d to scan %d (score %.3f) is %.3f m, %.3f rad off the corrected poses\n",
                     kind, c.from_scan, c.to_scan, c.score, std::hypot(diff.x, diff.y), diff.theta);
      }
    }
    return wrong;
  };
  const int wrong = count_wrong(slam.closures(), "loop closure");
  const int wrong_refinements = count_wrong(slam.refinements(), "refinement match");
  std::printf(
      "slam: %zu scans, %d nodes, %d loop closures (%d wrong) of %d attempts, %zu refinement matches (%d wrong), "
      "ATE RMSE %.4f m after SE(2) alignment, heading RMSE %.4f rad, worst %.3f m, %.2f ms per scan, "
      "relative error per scan step %.4f m, %.4f rad (mean; RMS along the travel %.4f m, across it %.4f m), "
      "ATE %.4f m after Sim(2) alignment at scale %.5f -> %s\n",
      estimate.size(), slam.nodes(), slam.loop_closures(), wrong, slam.loop_attempts(), slam.refinements().size(),
      wrong_refinements, error.position_rmse, error.heading_rmse, error.worst,
      1e3 * busy / static_cast<double>(estimate.size()), relative.translation_mean, relative.rotation_mean,
      relative.along_rmse, relative.across_rmse, error.similarity_rmse, error.scale, out.c_str());
  std::vector<std::vector<navd::Point2>> returns = ConsistencyReturns(log);
  const double at_estimate = navd::mapping::ScanConsistency(estimate, returns).Score().mean_distance;
  const double at_log = navd::mapping::ScanConsistency(truth, std::move(returns)).Score().mean_distance;
  std::printf(
      "scan consistency: returns %.1f mm from the lines the other scans draw at the estimate, %.1f mm at the "
      "log's poses\n",
      1e3 * at_estimate, 1e3 * at_log);
  if (tuning.learn_odometry_bias)
    std::printf("odometry bias learnt: scale %.4f, drift %.4f rad/m, turn error %.4f\n", slam.odometry_bias().scale(),
                slam.odometry_bias().drift(), slam.odometry_bias().turn_error());
  if (!graph_out.empty()) {
    WriteFileAtomically(graph_out, mapping::FormatG2o(slam.graph(), slam.node_scan_indices()));
    std::printf("pose graph: %d nodes (ids: their scans), %zu edges -> %s\n", slam.nodes(), slam.graph().edges().size(),
                graph_out.c_str());
  }
  if (!map_out.empty() || !png.empty()) {
    mapping::MapperOptions o;
    o.resolution = resolution;
    const OccupancyGrid grid = slam.RenderMap(o);
    NoteCoarserMap(grid, resolution);
    if (!map_out.empty()) SaveMapServerMap(grid, map_out);
    if (!png.empty()) SaveMapPng(grid, png);
    std::printf("map: %dx%d cells at %.3f m%s%s%s%s\n", grid.width(), grid.height(), grid.resolution(),
                map_out.empty() ? "" : " -> ", map_out.c_str(), png.empty() ? "" : " -> ", png.c_str());
  }
  return 0;
}

// m: the longest reading the localiser judges. Further, a reading's end is rarely on a mapped
// wall (the map is drawn to 15 m from each pose) and a heading error of a milliradian moves it
// more than a map cell; a scan with too little that near (an open hall) is judged to the far reach,
// as the map drew it (ScanReach).
constexpr navd::ScanReachOptions kLocalizationReach{25.0, 50.0};

navd::OccupancyGrid MapFromLog(const navd::CarmenLog& log, double resolution);

int BuildMap(const navd::CarmenLog& log, const std::string& out, double resolution, const std::string& png) {
  const navd::OccupancyGrid grid = MapFromLog(log, resolution);
  navd::SaveMapServerMap(grid, out);
  if (!png.empty()) navd::SaveMapPng(grid, png);
  std::printf("map: %dx%d cells at %.3f m, origin (%.2f, %.2f), from %zu scans -> %s\n", grid.width(), grid.height(),
              grid.resolution(), grid.origin().x(), grid.origin().y(), log.scans.size(), out.c_str());
  return 0;
}

// The particle filter's settings a run may change: its odometry noise (AMCL's alphas), the motion
// between the scans it weighs (AMCL's update_min_d, update_min_a; 0: the filter's defaults) and the
// particles it keeps once gathered. The estimate is their mean, as steady as they are many: on the
// real logs 2000 track 1-4 mm closer than navd's 500 (for navsim's robots, whose odometry arrives
// every few centimetres), at about a millisecond more per scan.
struct FilterTuning {
  double motion_noise = 0.0;
  double heading_per_metre_noise = 0.0;  // AMCL's alpha2 (rad² per m² driven) at least this
  double update_min_d = 0.0, update_min_a = 0.0;
  int min_particles = 2000;
};

int Localize(const navd::CarmenLog& log, const std::vector<navd::Pose2>& odometry, const std::string& out,
             const navd::OccupancyGrid& map, const navd::OdometryNoise& noise, uint64_t seed,
             const FilterTuning& tuning, const std::string& method) {
  using namespace navd;
  std::unique_ptr<localization::Localizer> localizer;
  if (method == "calibration") {
    localization::OdometricCalibrationOptions o;
    o.turn_threshold = 1e9;  // the log's scans are seconds apart: no turn rate to gate on
    localizer = std::make_unique<localization::OdometricCalibrationLocalizer>(map, o);
  } else if (method == "ekf") {
    // The filter's input noise is the replay's odometry noise model.
    localization::EkfOptions o;
    o.k_distance = noise.translation;
    o.k_turn = noise.translation;
    o.k_turn_per_metre = noise.rotation_per_metre;
    o.field.range_max = 20.0;
    localizer = std::make_unique<localization::EkfLocalizer>(map, o);
  } else {
    localization::ParticleFilterOptions o;
    o.seed = seed;
    o.range_max = 20.0;  // the z_rand density of a long-range (SICK) scanner's useful range
    o.alpha1 = o.alpha2 = o.alpha3 = o.alpha4 = tuning.motion_noise;
    o.alpha2 = std::max(o.alpha2, tuning.heading_per_metre_noise);
    if (tuning.update_min_d > 0.0) o.update_min_distance = tuning.update_min_d;
    if (tuning.update_min_a > 0.0) o.update_min_angle = tuning.update_min_a;
    o.min_particles = tuning.min_particles;
    o.max_particles = std::max(o.max_particles, o.min_particles);
    localizer = std::make_unique<localization::ParticleFilterLocalizer>(map, o);
  }
  localization::Localizer& pf = *localizer;
  pf.AddOdometry({odometry.front(), Eigen::Matrix3d::Zero(), log.scans.front().timestamp});
  pf.SetPose(log.scans.front().pose, Eigen::Matrix3d::Zero());
  std::string tum;
  double sq_pos = 0.0, sq_head = 0.0, worst = 0.0;
  std::vector<Pose2> estimate, truth;
  for (size_t k = 0; k < log.scans.size(); ++k) {
    const CarmenScan& s = log.scans[k];
    if (k > 0) pf.AddOdometry({odometry[k], Eigen::Matrix3d::Zero(), s.timestamp});
    localization::ScanReading scan;
    scan.ranges = s.ranges;
    scan.angle_min = s.angle_min;
    scan.angle_increment = s.angle_increment;
    scan.range_min = 0.05;
    // Beams are judged further than the map was drawn (its usable range): a corridor's far end,
    // mapped when the robot was nearer, is what holds the position along the corridor.
    scan.range_max = std::min(s.no_return_range(), ScanReach(s.ranges, s.no_return_range(), kLocalizationReach));
    scan.stamp = s.timestamp;
    pf.AddScan(scan);
    const Pose2 e = pf.Estimate().pose;
    estimate.push_back(e);
    truth.push_back(s.pose);
    const double ep = std::hypot(e.x - s.pose.x, e.y - s.pose.y), eh = std::abs(NormalizeAngle(e.theta - s.pose.theta));
    sq_pos += ep * ep;
    sq_head += eh * eh;
    worst = std::max(worst, ep);
    char line[160];
    std::snprintf(line, sizeof line, "%.6f %.6f %.6f 0 0 0 %.9f %.9f\n", s.timestamp, e.x, e.y, std::sin(e.theta / 2),
                  std::cos(e.theta / 2));
    tum += line;
    if ((k + 1) % 100 == 0 || k + 1 == log.scans.size())
      std::fprintf(stderr, "\r  localised %zu/%zu scans", k + 1, log.scans.size());
  }
  std::fprintf(stderr, "\n");
  WriteFileAtomically(out, tum);
  const double n_scans = static_cast<double>(log.scans.size());
  std::printf("localize (%s): %zu scans, position RMSE %.4f m, heading RMSE %.4f rad, worst %.3f m%s -> %s\n",
              method.c_str(), log.scans.size(), std::sqrt(sq_pos / n_scans), std::sqrt(sq_head / n_scans), worst,
              worst > 0.5 ? " (lost at times)" : ", never lost", out.c_str());
  // A map drawn in a frame of its own (a SLAM run's, which starts where its localiser put the
  // first scan) is judged by its shape: the trajectory on it aligned to the corrected poses.
  std::printf("localize: RMSE %.4f m after SE(2) alignment\n", AlignedTrajectoryError(estimate, truth).position_rmse);
  return 0;
}

navd::OccupancyGrid MapFromLog(const navd::CarmenLog& log, double resolution) {
  navd::mapping::MapperOptions o;
  o.resolution = resolution;
  navd::OccupancyGrid grid = navd::mapping::MapFromLogPoses(
      log, o, [](size_t done, size_t total) { std::fprintf(stderr, "\r  mapped %zu/%zu scans", done, total); });
  std::fprintf(stderr, "\n");
  NoteCoarserMap(grid, resolution);
  return grid;
}

// The log's scans cast again in the map its poses draw (log_renderer.h), written as a FLASER log.
int Render(const navd::CarmenLog& log, const std::string& out, double resolution,
           const navd::mapping::LogRenderOptions& options) {
  const navd::OccupancyGrid map = MapFromLog(log, resolution);
  // People walk by the clock: a log whose stamps say too little is paced from its motion first.
  // Without people the stamps are the log's own.
  navd::CarmenLog timed = log;
  if (options.people.count > 0) navd::PaceScansWhenStampsAreCoarse(timed);
  const navd::CarmenLog rendered = navd::mapping::RenderLog(timed, navd::RayCaster(map), options);
  navd::WriteFileAtomically(out, navd::FormatFlaserLog(rendered, "navd-replay"));
  std::printf(
      "render: %zu scans from the log's %zu, in its %dx%d-cell map at %.3f m, range noise %.3f m, %d people -> %s\n",
      rendered.scans.size(), log.scans.size(), map.width(), map.height(), map.resolution(), options.range_noise,
      options.people.count, out.c_str());
  return 0;
}

// One pose per non-empty, non-comment line of a TUM trajectory (t x y z qx qy qz qw), in order;
// throws std::runtime_error naming the file and line for a line that is not eight numbers.
std::vector<navd::Pose2> ReadTumTrajectory(const std::string& path) {
  std::vector<navd::Pose2> poses;
  const std::string text = navd::ReadTextFile(path, "--trajectory");
  size_t begin = 0;
  for (int number = 1; begin < text.size(); ++number) {
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(begin, end - begin);
    begin = end + 1;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
    double f[8];
    int used = 0;
    if (std::sscanf(line.c_str(), "%lf %lf %lf %lf %lf %lf %lf %lf %n", &f[0], &f[1], &f[2], &f[3], &f[4], &f[5], &f[6],
                    &f[7], &used) != 8 ||
        line.find_first_not_of(" \t\r", used) != std::string::npos)
      throw std::runtime_error(path + ":" + std::to_string(number) + ": not a TUM pose (t x y z qx qy qz qw)");
    const double qx = f[4], qy = f[5], qz = f[6], qw = f[7];
    const navd::Pose2 pose{f[1], f[2], std::atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))};
    if (!pose.finite()) throw std::runtime_error(path + ":" + std::to_string(number) + ": pose is not finite");
    poses.push_back(pose);
  }
  return poses;
}

// How well the log's scans agree at a trajectory's poses (`trajectory`, TUM, one line per scan in
// file order) or, without one, at the log's own: the mean, and per scan into `out` (scan, stamp,
// returns scored, mean distance in mm). With `scan` (0 or more) instead: where the other scans
// place that scan, searched every 5 cm up to 0.2 m and every 0.02 rad up to 0.24 rad around its
// pose.
int Consistency(const navd::CarmenLog& log, const std::string& trajectory, int scan, const std::string& out) {
  const std::vector<navd::Pose2> poses = trajectory.empty() ? LogPoses(log) : ReadTumTrajectory(trajectory);
  if (poses.size() != log.scans.size())
    throw std::runtime_error("--trajectory: " + std::to_string(poses.size()) + " poses for the log's " +
                             std::to_string(log.scans.size()) + " scans");
  // Searching for one scan's place, its returns look for lines twice as far and count up to 10 cm
  // off: a scan placed tens of centimetres and degrees off (a corrected log's error) has few of
  // its returns within the measure's 15 cm of a line, and the search would see no slope to its
  // place.
  navd::mapping::ScanConsistencyOptions options;
  if (scan >= 0) {
    options.neighbour_radius = 0.3;
    options.cap = 0.1;
  }
  const navd::mapping::ScanConsistency consistency(poses, ConsistencyReturns(log), options);
  const char* at = trajectory.empty() ? "the log's poses" : trajectory.c_str();
  if (scan >= 0) {
    if (scan >= static_cast<int>(poses.size()))
      throw std::runtime_error("--scan: the log has scans 0 to " + std::to_string(poses.size() - 1) + ", not " +
                               std::to_string(scan));
    // The best fit among the poses where at least as many of its returns find a line as at its own,
    // less a fifth: a pose that moves the scan off the walls it saw would be judged on the few
    // returns left.
    const navd::Pose2& own = poses[scan];
    const navd::mapping::ScanConsistency::ScanFit here = consistency.ScanAt(scan, own);
    if (here.scored == 0)
      throw std::runtime_error("--scan: no return of scan " + std::to_string(scan) +
                               " lies on a line the other scans draw at " + at);
    navd::mapping::ScanConsistency::ScanFit best = here;
    navd::Pose2 offset;
    for (int a = -12; a <= 12; ++a)
      for (int i = -4; i <= 4; ++i)
        for (int j = -4; j <= 4; ++j) {
          const navd::Pose2 moved{0.05 * i, 0.05 * j, 0.02 * a};
          const auto fit = consistency.ScanAt(scan, {own.x + moved.x, own.y + moved.y, own.theta + moved.theta});
          if (fit.scored >= 0.8 * here.scored && fit.mean_distance < best.mean_distance) {
            best = fit;
            offset = moved;
          }
        }
    navd::WriteFileAtomically(
        out, "# scan dx_m dy_m dtheta_rad mean_distance_mm own_mean_distance_mm\n" + std::to_string(scan) + " " +
                 std::to_string(offset.x) + " " + std::to_string(offset.y) + " " + std::to_string(offset.theta) + " " +
                 std::to_string(1e3 * best.mean_distance) + " " + std::to_string(1e3 * here.mean_distance) + "\n");
    std::printf(
        "consistency: scan %d at %s: %.2f mm from the other scans' lines, %.2f mm at its best, %+.2f m, "
        "%+.2f m, %+.2f rad from it (map frame) -> %s\n",
        scan, at, 1e3 * here.mean_distance, 1e3 * best.mean_distance, offset.x, offset.y, offset.theta, out.c_str());
    return 0;
  }
  const navd::mapping::ScanConsistencyResult result = consistency.Score();
  std::string table = "# scan stamp returns_scored mean_distance_mm\n";
  for (size_t i = 0; i < poses.size(); ++i) {
    char line[96];
    std::snprintf(line, sizeof line, "%zu %.6f %d %.2f\n", i, log.scans[i].timestamp, result.scan_scored[i],
                  1e3 * result.scan_mean_distance[i]);
    table += line;
  }
  navd::WriteFileAtomically(out, table);
  std::printf("consistency: %zu scans at %s, %lld returns scored, %.2f mm from the lines the other scans draw -> %s\n",
              poses.size(), at, result.scored, 1e3 * result.mean_distance, out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"navd-replay: navd's algorithms over a recorded CARMEN log"};
  std::string log_path, mode = "map", out;
  double resolution = 0.05;
  bool strict = false;
  app.add_option("--log", log_path, "CARMEN log (.log or .log.gz)")->required();
  app.add_option("--mode", mode,
                 "map: build a map from the log's corrected poses; localize: a localiser on a map; slam: graph SLAM "
                 "from corrupted odometry; render: the log's scans cast again in the map its poses draw; "
                 "consistency: how well the scans agree at the log's poses or --trajectory's")
      ->check(CLI::IsMember({"map", "localize", "slam", "render", "consistency"}));
  app.add_option("--out", out,
                 "Output: map_server YAML (map), TUM trajectory (localize, slam), CARMEN log (render) or each scan's "
                 "consistency (consistency)")
      ->required();
  navd::mapping::LogRenderOptions render;
  app.add_option("--step", render.step, "render: metres between rendered scans (default 0: at the log's own poses)")
      ->check(CLI::Range(0.0, 100.0));
  app.add_option("--turn", render.turn, "render: with --step, radians of turn between rendered scans")
      ->check(CLI::Range(0.001, 10.0));
  app.add_option("--range-noise", render.range_noise, "render: metres of Gaussian noise on each echo")
      ->check(CLI::Range(0.0, 1.0));
  double render_fov_degrees = 0.0;
  CLI::Option* fov_option =
      app.add_option("--fov", render_fov_degrees,
                     "render: with --beams, the scanner's field of view in degrees, centred ahead (default: the log's)")
          ->check(CLI::Range(0.01, 360.0));
  app.add_option("--beams", render.beams, "render: with --fov, the scanner's beam count, evenly apart")
      ->check(CLI::Range(2, navd::kMaxScanBeams))
      ->needs(fov_option);
  fov_option->needs("--beams");
  app.add_option("--people", render.people.count,
                 "render: people walking the log's path, back and forth at about 1 m/s (path_walkers.h)")
      ->check(CLI::Range(0, 10000));
  std::string trajectory;
  app.add_option("--trajectory", trajectory,
                 "consistency: a TUM trajectory (t x y z qx qy qz qw), one line per scan of the log in file order "
                 "(default: the log's poses)");
  int consistency_scan = -1;
  app.add_option("--scan", consistency_scan,
                 "consistency: where the other scans place this scan (from 0, in file order): the pose around its "
                 "own that fits them best")
      ->check(CLI::NonNegativeNumber);
  std::string map_out;
  app.add_option("--map-out", map_out, "slam: also write the map built as map_server YAML + PGM");
  std::string graph_out;
  app.add_option("--graph-out", graph_out,
                 "slam: also write the optimised pose graph in g2o's format (VERTEX_SE2 / EDGE_SE2; vertex ids: the "
                 "scans the nodes were made from)");
  std::string map_path, odom_noise = "0.05,0.035";
  uint64_t seed = 1;
  app.add_option("--map", map_path, "localize: map to localise on (default: built from the log's poses)");
  app.add_option("--odom-noise", odom_noise,
                 "localize, slam: T,R = relative translation noise, rad of heading noise per metre (slam: also the "
                 "noise its front end's window allows for, never less than the default, with --odometry log the "
                 "robot's); T,R,S,D also errs the same way every step (--odometry noisy): translation scaled by 1 + S, "
                 "heading drifting D rad per metre");
  std::string odometry_source = "noisy";
  app.add_option("--odometry", odometry_source,
                 "localize, slam: noisy (the log's laser poses corrupted by --odom-noise, seeded: the evaluation "
                 "protocol for corrected logs) or log (the odometry the log holds: ODOM lines taken to each scan as "
                 "--pairing says, else FLASER's odometry fields: raw logs)")
      ->check(CLI::IsMember({"noisy", "log"}));
  std::string pairing = "auto";
  app.add_option("--pairing", pairing,
                 "with --odometry log: how each scan takes the ODOM lines next to it: auto (as consecutive scans "
                 "matched against each other agree, default), stamp, or a share of the way from the line before "
                 "the scan (0) to the line after it (1), by stamp across a gap of over 1 s or where scans share "
                 "their two lines");
  app.add_option("--seed", seed,
                 "localize, slam: seed of the odometry noise (and the filter); render: of the range noise");
  // A log's own odometry errs beyond the front end's window between some scans (stamps that
  // cannot pair its ODOM lines with its scans, wheels slipping): by default, with --odometry log, matches
  // explaining less than 60 % of the local map are searched again wider (FrontEndRecovery).
  SlamTuning slam_tuning;
  slam_tuning.front_recovery = -1.0;
  app.add_option("--front-recovery", slam_tuning.front_recovery,
                 "slam: a front-end match scoring below this (0..1) is searched again over a wider window "
                 "(default: 0.6 with --odometry log, 0 (off) with --odometry noisy)")
      ->check(CLI::Range(0.0, 1.0));
  std::string odometry_bias = "auto";
  app.add_option("--odometry-bias", odometry_bias,
                 "slam: learn the odometry's systematic error (scale, heading drift, turn error) from the "
                 "well-matched steps and take it out of each step: on, off, or auto (default: on with "
                 "--odometry log, a robot's own; off with --odometry noisy, whose default model has none)")
      ->check(CLI::IsMember({"auto", "on", "off"}));
  app.add_option("--frame-turn", slam_tuning.frame_turn,
                 "slam: turn the map frame by this many radians at the first pose (the ATE is aligned; how much a "
                 "run owes to the grid's axes)")
      ->check(CLI::Range(-3.2, 3.2));
  app.add_flag("--drop-seen-through", slam_tuning.drop_seen_through,
               "slam: leave out of the references the returns another node saw through (people walking past; "
               "GraphSlamOptions::drop_seen_through)");
  app.add_option("--return-budget", slam_tuning.return_budget,
                 "slam: each scan's returns thinned to no fewer than this many before SLAM uses them (default " +
                     std::to_string(navd::kSickHalfDegreeBeams) +
                     "; a budget above the beam count keeps every return: GraphSlamOptions::return_budget)")
      ->check(CLI::Range(size_t{1}, static_cast<size_t>(navd::kMaxScanBeams)));
  std::string method = "amcl";
  app.add_option("--localizer", method,
                 "localize: amcl (particle filter, default), ekf (seed 002's EKF with scan-to-map matching) or "
                 "calibration (seed 000's odometric calibration)")
      ->check(CLI::IsMember({"amcl", "ekf", "calibration"}));
  // AMCL's alphas are variances per unit of motion squared. Unset: with --odometry noisy the
  // filter is told the noise the replay adds (alpha = T², a T standard deviation of each step's
  // translation and turn, and alpha2, the heading's per metre driven, at least R²); with --odometry log, whose noise is
  // unknown, 0.005 (7 % and 4 degrees per metre, a little above a well-kept differential drive's).
  double motion_noise = -1.0;
  FilterTuning tuning;
  app.add_option("--update-min-d", tuning.update_min_d,
                 "localize: the particle filter weighs a scan after this many metres of motion, AMCL's update_min_d "
                 "(default 0.05)")
      ->check(CLI::Range(1e-6, 100.0));
  app.add_option("--update-min-a", tuning.update_min_a,
                 "localize: ... or this many radians of turn, AMCL's update_min_a (default 0.05)")
      ->check(CLI::Range(1e-6, 10.0));
  app.add_option("--min-particles", tuning.min_particles,
                 "localize: the particles the filter keeps once its cloud has gathered, AMCL's min_particles "
                 "(default 2000)")
      ->check(CLI::Range(10, 100000));
  app.add_option("--motion-noise", motion_noise,
                 "localize: the filter's odometry noise alpha1..4 (variance per unit of motion squared; default: "
                 "T² of --odom-noise with --odometry noisy, 0.005 with --odometry log)")
      ->check(CLI::Range(0.0, 10.0));
  app.add_option("--resolution", resolution, "Map resolution, metres")->check(CLI::Range(0.005, 10.0));
  std::string png;
  app.add_option("--png", png, "map, slam: also write the map as a PNG image for people");
  app.add_flag("--strict", strict, "Stop at the first malformed line instead of skipping it");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (!graph_out.empty() && mode != "slam") {
    std::fprintf(stderr, "navd-replay: --graph-out is for --mode slam\n");
    return 2;
  }
  try {
    const auto t0 = std::chrono::steady_clock::now();
    const std::optional<navd::OdometryPairing> given_pairing = navd::ParseOdometryPairing(pairing, "--pairing");
    const navd::CarmenLog log = navd::ReadCarmenLog(log_path, strict);
    if (log.skipped_lines > 0) std::fprintf(stderr, "navd-replay: skipped %d malformed lines\n", log.skipped_lines);
    const navd::OdometryNoise noise = navd::ParseOdometryNoise(odom_noise);
    // map and render take the log's poses, no odometry
    std::vector<navd::Pose2> odometry;
    if (mode == "slam" || mode == "localize") {
      std::string how;
      odometry = navd::mapping::ReplayOdometryAtScans(
          log, odometry_source == "log" ? navd::mapping::OdometrySource::kLog : navd::mapping::OdometrySource::kNoisy,
          given_pairing, noise, seed, &how);
      if (!how.empty()) std::printf("odometry: %s\n", how.c_str());
    }
    int rc;
    if (mode == "map") {
      rc = BuildMap(log, out, resolution, png);
    } else if (mode == "consistency") {
      rc = Consistency(log, trajectory, consistency_scan, out);
    } else if (mode == "render") {
      render.fov = render_fov_degrees * M_PI / 180.0;
      render.seed = render.people.seed = seed;
      rc = Render(log, out, resolution, render);
    } else if (mode == "slam") {
      if (slam_tuning.front_recovery < 0.0)
        slam_tuning.front_recovery =
            odometry_source == "log" ? navd::mapping::RobotOdometryRecovery().below_score : 0.0;
      slam_tuning.learn_odometry_bias = odometry_bias == "on" || (odometry_bias == "auto" && odometry_source == "log");
      // Never less than the default model: a replay that adds no noise (--odom-noise 0,0) is run on
      // logs whose own poses are odometry already.
      const navd::OdometryNoise least;
      slam_tuning.odometry = {std::max(noise.translation, least.translation),
                              std::max(noise.rotation_per_metre, least.rotation_per_metre)};
      rc = Slam(log, odometry, slam_tuning, out, map_out, graph_out, png, resolution);
    } else {
      const navd::OccupancyGrid map = map_path.empty() ? MapFromLog(log, resolution) : navd::LoadAnyMapFile(map_path);
      if (motion_noise < 0.0 && odometry_source == "log") {
        motion_noise = 0.005;
      } else if (motion_noise < 0.0) {
        motion_noise = noise.translation * noise.translation;
        tuning.heading_per_metre_noise = noise.rotation_per_metre * noise.rotation_per_metre;
      }
      tuning.motion_noise = motion_noise;
      rc = Localize(log, odometry, out, map, noise, seed, tuning, method);
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double span = log.scans.back().timestamp - log.scans.front().timestamp;
    std::printf("replayed %.0f s of log in %.2f s (%.0fx real time)\n", span, wall, wall > 0 ? span / wall : 0.0);
    return rc;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navd-replay: %s\n", e.what());
    return 2;
  }
}
