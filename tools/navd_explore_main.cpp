// navd-explore: autonomous exploration of a simulated world from an empty map, in one process
// with navd's library code: the simulator (navsim's Simulation, unpaced), graph SLAM from the
// robot's odometry and laser (MappingSession), the exploration goal and path
// (NextExplorationStep: greedy, frontier or Voronoi Fast Marching) and seed 000's path follower.
// The robot knows its start pose and nothing of the map. It stops when no reachable frontier is
// left, or at --max-time. Prints the share of the reachable free space mapped, simulated time,
// path length and collisions. --record writes the robot's run as a CARMEN log (navsim's recorder: the
// laser at the true pose, as in a corrected log), a dense log for navd-replay:
//   navd-explore [--world FILE] --method greedy|frontier|vfm [--max-time 900] [--png MAP.png] [--seed N]
//                [--record LOG]
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "services/common/diff_drive.h"
#include "services/common/error.h"
#include "services/common/png_format.h"
#include "services/common/world.h"
#include "services/localization/odometry_history.h"
#include "services/mapping/map_coverage.h"
#include "services/mapping/mapping_session.h"
#include "services/navigation/frontier_exploration.h"
#include "services/navigation/path_follower.h"
#include "simulator/carmen_recorder.h"
#include "simulator/simulation.h"

namespace {

using namespace navd;

// What one run does and writes (navd-explore's options).
struct ExploreOptions {
  navigation::ExplorationMethod method = navigation::ExplorationMethod::kFrontier;
  std::string method_name = "frontier";
  double max_time = 900.0;  // s of simulated time
  std::string png;          // the map built, as a PNG ('' for none)
  uint64_t seed = 1;        // the simulator's
  std::string record;       // the run as a CARMEN log ('' for none)
};

// One exploration run: the simulated robot, its SLAM from odometry and laser, and the goal it
// drives to, chosen again once a second, on arrival (after half a turn on the spot) or when the
// robot makes no progress for 20 s.
class ExplorationRun {
 public:
  ExplorationRun(const World& world, const ExploreOptions& options)
      : world_(world),
        o_(options),
        sim_(world,
             [&] {
               sim::SimulationOptions so;
               so.seed = options.seed;
               return so;
             }()),
        recorder_(options.record.empty() ? nullptr
                                         : std::make_unique<sim::CarmenRecorder>(
                                               options.record, "navd-explore " + options.method_name + ", seed " +
                                                                   std::to_string(options.seed))),
        session_(SessionOptions(world), world.start),
        follower_(FollowerParams(world)),
        odometry_(256),
        slam_at_scan_(world.start),
        odom_at_scan_(sim_.robot().base().odom_pose()),
        estimate_(world.start),
        visited_{world.start.translation()},
        last_true_(sim_.robot().base().true_pose().translation()),
        goal_(world.start.translation()) {
    eo_.clearance = world.robot.radius + 0.15;
  }

  // Explores until no reachable frontier is left (exit code 0) or --max-time (3), then reports.
  int Run() {
    bool complete = false;
    while (sim_.now() < o_.max_time) {
      Step();
      const Decision decision = Decide();
      if (decision == Decision::kComplete) {
        complete = true;
        break;
      }
      if (decision == Decision::kTurning) continue;
      if (sim_.now() > 2.0 && static_cast<int>(sim_.now() * 100) % 3000 == 0)
        std::fprintf(stderr, "\r  %s: %.0f s simulated, %.1f m driven, %d goals", o_.method_name.c_str(), sim_.now(),
                     travelled_, goals_);
    }
    std::fprintf(stderr, "\n");
    session_.Finish();
    Report(complete);
    return complete ? 0 : 3;
  }

 private:
  static mapping::MappingSessionOptions SessionOptions(const World& world) {
    mapping::MappingSessionOptions mo;
    mo.mode = mapping::MappingMode::kSlam;
    mo.synchronous = true;
    mo.size = std::max(world.map.size_x(), world.map.size_y()) * 2.0 + 8.0;
    return mo;
  }

  static navigation::PathFollowerParams FollowerParams(const World& world) {
    navigation::PathFollowerParams fp;
    fp.wheel_base = world.robot.wheel_base;
    fp.max_wheel_speed = world.robot.max_wheel_speed;
    fp.v_nav = std::min(0.4, world.robot.max_wheel_speed);
    fp.waypoint_radius = 0.15;  // follow the path closely: it keeps its clearance, rounded corners do not
    return fp;
  }

  // One simulator step: the follower's command (or the turn on the spot), each scan to SLAM and the
  // recorder, the estimate carried by odometry, the distance driven.
  void Step() {
    WheelSpeeds wheels = follower_.Step(estimate_).wheels;
    if (sim_.now() < look_around_until_) wheels = {-0.2, 0.2};
    const Twist2 twist = ToTwist(wheels, world_.robot.wheel_base);
    sim_.Command(0, {twist.v, 0.0, twist.omega});
    const sim::StepOutputs out = sim_.Step();
    collisions_ += static_cast<int>(out.events.size());
    const Pose2 odom_now = sim_.robot().base().odom_pose();
    if (out.robots[0].odom) odometry_.Add({odom_now, sim_.robot().base().odom_covariance(), sim_.now()});
    if (out.robots[0].scan && !odometry_.empty()) Sense(*out.robots[0].scan);
    // The SLAM pose of the last scan, carried to now by odometry.
    estimate_ = slam_at_scan_ * (odom_at_scan_.inverse() * odom_now);
    const Point2 now_true = sim_.robot().base().true_pose().translation();
    travelled_ += Distance(last_true_, now_true);
    last_true_ = now_true;
    if (Distance(visited_.back(), estimate_.translation()) > 0.5) visited_.push_back(estimate_.translation());
  }

  void Sense(const std::vector<float>& ranges) {
    mapping::RangeScan scan{ranges, sim_.robot().laser()->angle_min(), sim_.robot().laser()->increment(), sim_.now(),
                            world_.laser.range_max};
    odom_at_scan_ = odometry_.At(sim_.now());
    session_.Submit(odom_at_scan_, estimate_, scan);
    slam_at_scan_ = session_.status().pose;
    if (recorder_) {
      const auto& base = sim_.robot().base();
      recorder_->Laser(sim_.now(), world_.laser, scan.angle_min, scan.angle_increment, scan.ranges, base.true_pose(),
                       base.odom_pose(), base.odom_twist().vx, base.odom_twist().omega);
    }
  }

  enum class Decision {
    kTurning,   // turning on the spot after an arrival
    kDriving,   // on the way to the goal, a new one chosen if one was due
    kComplete,  // no reachable frontier is left
  };

  // The goal's progress, the turn on the spot on arrival, and a new goal when one is due.
  Decision Decide() {
    const double remaining = Distance(estimate_.translation(), goal_);
    if (remaining < best_remaining_ - 0.05) {
      best_remaining_ = remaining;
      last_progress_time_ = sim_.now();
    }
    const bool arrived = follower_.state() == navigation::FollowerState::kArrived ||
                         follower_.state() == navigation::FollowerState::kIdle;
    const bool stuck = sim_.now() - last_progress_time_ > 20.0;
    if (sim_.now() < look_around_until_) return Decision::kTurning;
    if (arrived && goals_ > 0 && look_around_until_ < 0.0) {
      // Arrived: half a turn on the spot first (the laser sees 240 degrees), then plan again.
      look_around_until_ = sim_.now() + 2.5;
      follower_.Clear();
      return Decision::kTurning;
    }
    const bool done = (arrived && look_around_until_ >= 0.0) || stuck;
    if (sim_.now() < next_plan_ && !done) return Decision::kDriving;
    if (done) eo_.excluded.push_back(goal_);  // this goal is done or out of reach
    look_around_until_ = -1.0;
    next_plan_ = sim_.now() + 1.0;
    const auto step = navigation::NextExplorationStep(*session_.Map(), estimate_, o_.method, visited_, eo_);
    if (!step) return Decision::kComplete;
    if (Distance(step->goal, goal_) > 0.3) {
      ++goals_;
      best_remaining_ = 1e9;
      last_progress_time_ = sim_.now();
    }
    goal_ = step->goal;
    follower_.SetPath(step->path, std::nullopt);
    return Decision::kDriving;
  }

  // Coverage: the reachable free cells of the truth that the built map shows.
  void Report(bool complete) {
    const auto built = session_.Map();
    const mapping::MapCoverage coverage = mapping::CoverageOf(*built, world_.map, world_.start.translation());
    const mapping::MappingStatus st = session_.status();
    std::printf(
        "explore (%s): %s, %.1f%% of the reachable free space mapped (%.1f%% mapped free), %.1f s simulated, "
        "%.1f m driven, %d goals, %d collisions, %d SLAM nodes, %d loop closures\n",
        o_.method_name.c_str(), complete ? "complete" : "stopped at --max-time", 100.0 * coverage.known,
        100.0 * coverage.known_free, sim_.now(), travelled_, goals_, collisions_, st.nodes, st.loop_closures);
    if (!o_.png.empty()) SaveMapPng(*built, o_.png);
    if (recorder_) recorder_->Close();
  }

  const World& world_;
  const ExploreOptions o_;
  sim::Simulation sim_;
  std::unique_ptr<sim::CarmenRecorder> recorder_;
  mapping::MappingSession session_;
  navigation::PathFollower follower_;
  navigation::ExplorationOptions eo_;
  localization::OdometryHistory odometry_;
  Pose2 slam_at_scan_, odom_at_scan_, estimate_;
  std::vector<Point2> visited_;
  Point2 last_true_;
  double travelled_ = 0.0, next_plan_ = 0.0, last_progress_time_ = 0.0, best_remaining_ = 1e9;
  int collisions_ = 0, goals_ = 0;
  Point2 goal_;
  double look_around_until_ = -1.0;  // after each arrival the robot turns on the spot, seeing its blind side
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "navd-explore: explore a simulated world from an empty map with navd's SLAM, exploration and path following"};
  std::string world_path;
  ExploreOptions o;
  app.add_option("--world", world_path, "World YAML or map (default: the embedded warehouse)");
  app.add_option("--method", o.method_name,
                 "greedy (seed 002), frontier (Yamauchi) or vfm (book ch. 4 Voronoi Fast Marching)")
      ->check(CLI::IsMember({"greedy", "frontier", "vfm"}));
  app.add_option("--max-time", o.max_time, "Seconds of simulated time at most")->check(CLI::Range(1.0, 86400.0));
  app.add_option("--png", o.png, "Write the map built as a PNG");
  app.add_option("--seed", o.seed, "Simulator seed (sensor and odometry noise)");
  app.add_option("--record", o.record, "Write the run as a CARMEN log (ROBOTLASER1 at the true pose) to this file");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    const navd::World world = world_path.empty() ? navd::DefaultWorld() : navd::LoadWorldOrMapFile(world_path);
    o.method = navd::navigation::ParseExplorationMethod(o.method_name);
    return ExplorationRun(world, o).Run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navd-explore: %s\n", e.what());
    return 2;
  }
}
