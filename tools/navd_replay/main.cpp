// navd-replay: runs navd's library code over a recorded CARMEN log, as fast as it can.
//   navd-replay --log FILE[.gz] --mode map --out MAP.yaml [--resolution 0.05] [--png MAP.png]
//   navd-replay --log FILE[.gz] --mode render --out RENDERED.log [--step M] [--turn RAD] [--range-noise M]
//               [--people N] [--fov DEG --beams N] [--seed N] [--resolution M]
//   navd-replay --log FILE[.gz] --mode localize --out EST.tum [--odometry noisy|log] [--pairing P]
//               [--map MAP.yaml] [--odom-noise T,R[,S,D]] [--seed N] [--localizer amcl|ekf|calibration]
//               [--update-min-d M] [--update-min-a RAD] [--min-particles N] [--motion-noise A]
//   navd-replay --log FILE[.gz] --mode slam --out EST.tum [--odometry noisy|log] [--pairing P]
//               [--odom-noise T,R[,S,D]] [--seed N] [--front-recovery SCORE] [--odometry-bias auto|on|off]
//               [--frame-turn RAD] [--drop-seen-through] [--return-budget N] [--map-out MAP.yaml]
//               [--png MAP.png] [--graph-out GRAPH.g2o]
//   navd-replay --log FILE[.gz] --mode consistency --out SCANS.txt [--trajectory EST.tum] [--scan K]
// An option given to a mode not listed with it is refused, and --pairing without --odometry log
// (OptionScopes); so is one its mode takes only beside another: --resolution in slam without
// --map-out or --png, or in localize with --map; --seed with --odometry log but for amcl
// localisation (OptionWithoutEffect).
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
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "services/common/carmen_log.h"
#include "services/common/odometry_noise.h"
#include "services/common/scan_reach.h"
#include "services/common/world.h"
#include "services/mapping/front_end_recovery.h"
#include "services/mapping/log_renderer.h"
#include "services/mapping/odometry_pairing.h"
#include "tools/navd_replay/log_consistency.h"
#include "tools/navd_replay/log_localization.h"
#include "tools/navd_replay/log_map.h"
#include "tools/navd_replay/log_slam.h"

namespace {

// Where each option of one mode (or one odometry source) works: given elsewhere it would be
// ignored, and a run the user thinks tuned or saved something would have done neither.
struct OptionScope {
  const char* option;
  std::vector<std::string> values;  // the values of `by` it works under
  const char* by = "--mode";
};

const std::vector<OptionScope>& OptionScopes() {
  static const std::vector<OptionScope> scopes = {
      {"--step", {"render"}},
      {"--turn", {"render"}},
      {"--range-noise", {"render"}},
      {"--fov", {"render"}},
      {"--beams", {"render"}},
      {"--people", {"render"}},
      {"--trajectory", {"consistency"}},
      {"--scan", {"consistency"}},
      {"--map-out", {"slam"}},
      {"--graph-out", {"slam"}},
      {"--front-recovery", {"slam"}},
      {"--odometry-bias", {"slam"}},
      {"--frame-turn", {"slam"}},
      {"--drop-seen-through", {"slam"}},
      {"--return-budget", {"slam"}},
      {"--map", {"localize"}},
      {"--localizer", {"localize"}},
      {"--update-min-d", {"localize"}},
      {"--update-min-a", {"localize"}},
      {"--min-particles", {"localize"}},
      {"--motion-noise", {"localize"}},
      {"--odom-noise", {"localize", "slam"}},
      {"--odometry", {"localize", "slam"}},
      {"--pairing", {"localize", "slam"}},
      {"--seed", {"localize", "slam", "render"}},
      {"--png", {"map", "slam"}},
      {"--resolution", {"map", "render", "localize", "slam"}},
      // It pairs the log's own ODOM lines with its scans.
      {"--pairing", {"log"}, "--odometry"},
  };
  return scopes;
}

// "--X is for --mode a|b, not c" for the first option given where it does not work; "" when none
// is. `value_of`: the value given to each option a scope names (--mode, --odometry).
std::string OptionOutsideItsScope(const CLI::App& app, const std::map<std::string, std::string>& value_of) {
  for (const OptionScope& scope : OptionScopes()) {
    const std::string& value = value_of.at(scope.by);
    if (app.get_option(scope.option)->count() == 0 ||
        std::find(scope.values.begin(), scope.values.end(), value) != scope.values.end())
      continue;
    std::string values;
    for (const std::string& v : scope.values) values += (values.empty() ? "" : "|") + v;
    return std::string(scope.option) + " is for " + scope.by + " " + values + ", not " + value;
  }
  return "";
}

// Options that work in their mode only beside another option (or without one): given otherwise
// they would change nothing. "" when none is given so.
std::string OptionWithoutEffect(const CLI::App& app, const std::string& mode, const std::string& odometry,
                                const std::string& localizer) {
  const auto given = [&app](const char* option) { return app.get_option(option)->count() > 0; };
  if (given("--resolution") && mode == "slam" && !given("--map-out") && !given("--png"))
    return "--resolution in --mode slam is the resolution of the map it writes: add --map-out or --png";
  if (given("--resolution") && mode == "localize" && given("--map"))
    return "--resolution is for the map drawn from the log's poses, and --map brings its own";
  // The seed draws the noise of --odometry noisy and the particle filter's samples, nothing else.
  if (given("--seed") && odometry == "log" && (mode == "slam" || (mode == "localize" && localizer != "amcl")))
    return "--seed with --odometry log is for --mode localize --localizer amcl (the particle filter) only";
  return "";
}

// Everything navd-replay's command line says; RunSlam and RunLocalize fill in place what it left open.
struct CommandLine {
  std::string log_path, mode = "map", out;
  double resolution = 0.05;
  bool strict = false;
  std::string png;
  // render
  navd::mapping::LogRenderOptions render;
  double render_fov_degrees = 0.0;
  // consistency
  std::string trajectory;
  int consistency_scan = -1;
  // localize, slam
  std::string odom_noise = "0.05,0.035", odometry_source = "noisy", pairing = "auto";
  uint64_t seed = 1;
  // slam
  navd::replay::SlamRunOptions slam;
  std::string map_out, graph_out, odometry_bias = "auto";
  // localize
  navd::replay::LocalizationRunOptions localization;
  std::string map_path;
  double motion_noise = -1.0;  // unset: from the odometry's source
};

void AddCommonOptions(CLI::App& app, CommandLine& c) {
  app.add_option("--log", c.log_path, "CARMEN log (.log or .log.gz)")->required();
  app.add_option("--mode", c.mode,
                 "map: build a map from the log's corrected poses; localize: a localiser on a map; slam: graph SLAM "
                 "from corrupted odometry; render: the log's scans cast again in the map its poses draw; "
                 "consistency: how well the scans agree at the log's poses or --trajectory's")
      ->check(CLI::IsMember({"map", "localize", "slam", "render", "consistency"}));
  app.add_option("--out", c.out,
                 "Output: map_server YAML (map), TUM trajectory (localize, slam), CARMEN log (render) or each scan's "
                 "consistency (consistency)")
      ->required();
}

void AddRenderOptions(CLI::App& app, CommandLine& c) {
  app.add_option("--step", c.render.step, "render: metres between rendered scans (default 0: at the log's own poses)")
      ->check(CLI::Range(0.0, 100.0));
  app.add_option("--turn", c.render.turn, "render: with --step, radians of turn between rendered scans")
      ->check(CLI::Range(0.001, 10.0));
  app.add_option("--range-noise", c.render.range_noise, "render: metres of Gaussian noise on each echo")
      ->check(CLI::Range(0.0, 1.0));
  CLI::Option* fov_option =
      app.add_option("--fov", c.render_fov_degrees,
                     "render: with --beams, the scanner's field of view in degrees, centred ahead (default: the log's)")
          ->check(CLI::Range(0.01, 360.0));
  app.add_option("--beams", c.render.beams, "render: with --fov, the scanner's beam count, evenly apart")
      ->check(CLI::Range(2, navd::kMaxScanBeams))
      ->needs(fov_option);
  fov_option->needs("--beams");
  app.add_option("--people", c.render.people.count,
                 "render: people walking the log's path, back and forth at about 1 m/s (path_walkers.h)")
      ->check(CLI::Range(0, 10000));
}

void AddConsistencyOptions(CLI::App& app, CommandLine& c) {
  app.add_option("--trajectory", c.trajectory,
                 "consistency: a TUM trajectory (t x y z qx qy qz qw), one line per scan of the log in file order "
                 "(default: the log's poses)");
  app.add_option("--scan", c.consistency_scan,
                 "consistency: where the other scans place this scan (from 0, in file order): the pose around its "
                 "own that fits them best")
      ->check(CLI::NonNegativeNumber);
}

// What localize and slam share: where the odometry comes from, and its noise.
void AddOdometryOptions(CLI::App& app, CommandLine& c) {
  app.add_option("--odom-noise", c.odom_noise,
                 "localize, slam: T,R = relative translation noise, rad of heading noise per metre (slam: also the "
                 "noise its front end's window allows for, never less than the default, with --odometry log the "
                 "robot's); T,R,S,D also errs the same way every step (--odometry noisy): translation scaled by 1 + S, "
                 "heading drifting D rad per metre");
  app.add_option("--odometry", c.odometry_source,
                 "localize, slam: noisy (the log's laser poses corrupted by --odom-noise, seeded: the evaluation "
                 "protocol for corrected logs) or log (the odometry the log holds: ODOM lines taken to each scan as "
                 "--pairing says, else FLASER's odometry fields: raw logs)")
      ->check(CLI::IsMember({"noisy", "log"}));
  app.add_option(
      "--pairing", c.pairing,
      "localize, slam: with --odometry log: how each scan takes the ODOM lines next to it: auto (as consecutive scans "
      "matched against each other agree, default), stamp, or a share of the way from the line before "
      "the scan (0) to the line after it (1), by stamp across a gap of over 1 s or where scans share "
      "their two lines");
  app.add_option("--seed", c.seed,
                 "localize, slam: seed of the odometry noise (and the filter); render: of the range noise");
}

void AddSlamOptions(CLI::App& app, CommandLine& c) {
  app.add_option("--map-out", c.map_out, "slam: also write the map built as map_server YAML + PGM");
  app.add_option("--graph-out", c.graph_out,
                 "slam: also write the optimised pose graph in g2o's format (VERTEX_SE2 / EDGE_SE2; vertex ids: the "
                 "scans the nodes were made from)");
  // A log's own odometry errs beyond the front end's window between some scans (stamps that
  // cannot pair its ODOM lines with its scans, wheels slipping): by default, with --odometry log, matches
  // explaining less than 60 % of the local map are searched again wider (FrontEndRecovery).
  c.slam.front_recovery = -1.0;
  app.add_option("--front-recovery", c.slam.front_recovery,
                 "slam: a front-end match scoring below this (0..1) is searched again over a wider window "
                 "(default: 0.6 with --odometry log, 0 (off) with --odometry noisy)")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--odometry-bias", c.odometry_bias,
                 "slam: learn the odometry's systematic error (scale, heading drift, turn error) from the "
                 "well-matched steps and take it out of each step: on, off, or auto (default: on with "
                 "--odometry log, a robot's own; off with --odometry noisy, whose default model has none)")
      ->check(CLI::IsMember({"auto", "on", "off"}));
  app.add_option("--frame-turn", c.slam.frame_turn,
                 "slam: turn the map frame by this many radians at the first pose (the ATE is aligned; how much a "
                 "run owes to the grid's axes)")
      ->check(CLI::Range(-3.2, 3.2));
  app.add_flag("--drop-seen-through", c.slam.drop_seen_through,
               "slam: leave out of the references the returns another node saw through (people walking past; "
               "GraphSlamOptions::drop_seen_through)");
  app.add_option("--return-budget", c.slam.return_budget,
                 "slam: each scan's returns thinned to no fewer than this many before SLAM uses them (default " +
                     std::to_string(navd::kSickHalfDegreeBeams) +
                     "; a budget above the beam count keeps every return: GraphSlamOptions::return_budget)")
      ->check(CLI::Range(size_t{1}, static_cast<size_t>(navd::kMaxScanBeams)));
}

void AddLocalizeOptions(CLI::App& app, CommandLine& c) {
  app.add_option("--map", c.map_path, "localize: map to localise on (default: built from the log's poses)");
  app.add_option("--localizer", c.localization.method,
                 "localize: amcl (particle filter, default), ekf (seed 002's EKF with scan-to-map matching) or "
                 "calibration (seed 000's odometric calibration)")
      ->check(CLI::IsMember({"amcl", "ekf", "calibration"}));
  app.add_option("--update-min-d", c.localization.filter.update_min_d,
                 "localize: the particle filter weighs a scan after this many metres of motion, AMCL's update_min_d "
                 "(default 0.05)")
      ->check(CLI::Range(1e-6, 100.0));
  app.add_option("--update-min-a", c.localization.filter.update_min_a,
                 "localize: ... or this many radians of turn, AMCL's update_min_a (default 0.05)")
      ->check(CLI::Range(1e-6, 10.0));
  app.add_option("--min-particles", c.localization.filter.min_particles,
                 "localize: the particles the filter keeps once its cloud has gathered, AMCL's min_particles "
                 "(default 2000)")
      ->check(CLI::Range(10, 100000));
  app.add_option("--motion-noise", c.motion_noise,
                 "localize: the filter's odometry noise alpha1..4 (variance per unit of motion squared; default: "
                 "T² of --odom-noise with --odometry noisy, 0.005 with --odometry log)")
      ->check(CLI::Range(0.0, 10.0));
}

int RunSlam(const navd::CarmenLog& log, const std::vector<navd::Pose2>& odometry, const navd::OdometryNoise& noise,
            CommandLine& c) {
  navd::replay::SlamRunOptions& slam = c.slam;
  if (slam.front_recovery < 0.0)
    slam.front_recovery = c.odometry_source == "log" ? navd::mapping::RobotOdometryRecovery().below_score : 0.0;
  slam.learn_odometry_bias = c.odometry_bias == "on" || (c.odometry_bias == "auto" && c.odometry_source == "log");
  // Never less than the default model: a replay that adds no noise (--odom-noise 0,0) is run on
  // logs whose own poses are odometry already.
  const navd::OdometryNoise least;
  slam.odometry = {std::max(noise.translation, least.translation),
                   std::max(noise.rotation_per_metre, least.rotation_per_metre)};
  slam.out = c.out;
  slam.map_out = c.map_out;
  slam.graph_out = c.graph_out;
  slam.png = c.png;
  slam.resolution = c.resolution;
  return navd::replay::Slam(log, odometry, slam);
}

int RunLocalize(const navd::CarmenLog& log, const std::vector<navd::Pose2>& odometry, const navd::OdometryNoise& noise,
                CommandLine& c) {
  const navd::OccupancyGrid map =
      c.map_path.empty() ? navd::replay::MapFromLog(log, c.resolution) : navd::LoadAnyMapFile(c.map_path);
  navd::replay::LocalizationRunOptions& localization = c.localization;
  // AMCL's alphas are variances per unit of motion squared. Unset: with --odometry noisy the
  // filter is told the noise the replay adds (alpha = T², a T standard deviation of each step's
  // translation and turn, and alpha2, the heading's per metre driven, at least R²); with --odometry log, whose noise is
  // unknown, 0.005 (7 % and 4 degrees per metre, a little above a well-kept differential drive's).
  double motion_noise = c.motion_noise;
  if (motion_noise < 0.0 && c.odometry_source == "log") {
    motion_noise = 0.005;
  } else if (motion_noise < 0.0) {
    motion_noise = noise.translation * noise.translation;
    localization.filter.heading_per_metre_noise = noise.rotation_per_metre * noise.rotation_per_metre;
  }
  localization.filter.motion_noise = motion_noise;
  localization.noise = noise;
  localization.seed = c.seed;
  localization.out = c.out;
  return navd::replay::Localize(log, odometry, map, localization);
}

// Reads the log and runs the mode; throws for one readable line.
int Run(CommandLine& c) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::optional<navd::OdometryPairing> given_pairing = navd::ParseOdometryPairing(c.pairing, "--pairing");
  const navd::CarmenLog log = navd::ReadCarmenLog(c.log_path, c.strict);
  if (log.skipped_lines > 0) std::fprintf(stderr, "navd-replay: skipped %d malformed lines\n", log.skipped_lines);
  const navd::OdometryNoise noise = navd::ParseOdometryNoise(c.odom_noise);
  // map and render take the log's poses, no odometry
  std::vector<navd::Pose2> odometry;
  if (c.mode == "slam" || c.mode == "localize") {
    std::string how;
    odometry = navd::mapping::ReplayOdometryAtScans(
        log, c.odometry_source == "log" ? navd::mapping::OdometrySource::kLog : navd::mapping::OdometrySource::kNoisy,
        given_pairing, noise, c.seed, &how);
    if (!how.empty()) std::printf("odometry: %s\n", how.c_str());
  }
  int rc;
  if (c.mode == "map") {
    rc = navd::replay::BuildMap(log, c.out, c.resolution, c.png);
  } else if (c.mode == "consistency") {
    rc = navd::replay::Consistency(log, c.trajectory, c.consistency_scan, c.out);
  } else if (c.mode == "render") {
    c.render.fov = c.render_fov_degrees * M_PI / 180.0;
    c.render.seed = c.render.people.seed = c.seed;
    rc = navd::replay::Render(log, c.out, c.resolution, c.render);
  } else if (c.mode == "slam") {
    rc = RunSlam(log, odometry, noise, c);
  } else {
    rc = RunLocalize(log, odometry, noise, c);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double span = log.scans.back().timestamp - log.scans.front().timestamp;
  std::printf("replayed %.0f s of log in %.2f s (%.0fx real time)\n", span, wall, wall > 0 ? span / wall : 0.0);
  return rc;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"navd-replay: navd's algorithms over a recorded CARMEN log"};
  CommandLine c;
  AddCommonOptions(app, c);
  AddRenderOptions(app, c);
  AddConsistencyOptions(app, c);
  AddSlamOptions(app, c);
  AddOdometryOptions(app, c);
  AddLocalizeOptions(app, c);
  app.add_option("--resolution", c.resolution, "map, render, localize, slam: the map's resolution, metres")
      ->check(CLI::Range(0.005, 10.0));
  app.add_option("--png", c.png, "map, slam: also write the map as a PNG image for people");
  app.add_flag("--strict", c.strict, "Stop at the first malformed line instead of skipping it");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  std::string misplaced = OptionOutsideItsScope(app, {{"--mode", c.mode}, {"--odometry", c.odometry_source}});
  if (misplaced.empty()) misplaced = OptionWithoutEffect(app, c.mode, c.odometry_source, c.localization.method);
  if (!misplaced.empty()) {
    std::fprintf(stderr, "navd-replay: %s\n", misplaced.c_str());
    return 2;
  }
  try {
    return Run(c);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navd-replay: %s\n", e.what());
    return 2;
  }
}
