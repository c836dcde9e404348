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

int Explore(const World& world, navigation::ExplorationMethod method, const std::string& method_name, double max_time,
            const std::string& png, uint64_t seed, const std::string& record) {
  sim::SimulationOptions so;
  so.seed = seed;
  sim::Simulation sim(world, so);
  std::unique_ptr<sim::CarmenRecorder> recorder;
  if (!record.empty())
    recorder =
        std::make_unique<sim::CarmenRecorder>(record, "navd-explore " + method_name + ", seed " + std::to_string(seed));
  const double wheel_base = world.robot.wheel_base;

  mapping::MappingSessionOptions mo;
  mo.mode = mapping::MappingMode::kSlam;
  mo.synchronous = true;
  mo.size = std::max(world.map.size_x(), world.map.size_y()) * 2.0 + 8.0;
  mapping::MappingSession session(mo, world.start);

  navigation::PathFollowerParams fp;
  fp.wheel_base = wheel_base;
  fp.max_wheel_speed = world.robot.max_wheel_speed;
  fp.v_nav = std::min(0.4, world.robot.max_wheel_speed);
  fp.waypoint_radius = 0.15;  // follow the path closely: it keeps its clearance, rounded corners do not
  navigation::PathFollower follower(fp);
  navigation::ExplorationOptions eo;
  eo.clearance = world.robot.radius + 0.15;

  localization::OdometryHistory odometry(256);
  Pose2 slam_at_scan = world.start, odom_at_scan = sim.robot().base().odom_pose();
  Pose2 estimate = world.start;
  std::vector<Point2> visited{world.start.translation()};
  Point2 last_true = sim.robot().base().true_pose().translation();
  double travelled = 0.0, next_plan = 0.0, last_progress_time = 0.0, best_remaining = 1e9;
  int collisions = 0, goals = 0;
  bool complete = false;
  Point2 goal = world.start.translation();
  double look_around_until = -1.0;  // after each arrival the robot turns on the spot, seeing its blind side

  while (sim.now() < max_time) {
    WheelSpeeds wheels = follower.Step(estimate).wheels;
    if (sim.now() < look_around_until) wheels = {-0.2, 0.2};
    const Twist2 twist = ToTwist(wheels, wheel_base);
    sim.Command(0, {twist.v, 0.0, twist.omega});
    const sim::StepOutputs out = sim.Step();
    collisions += static_cast<int>(out.events.size());
    const Pose2 odom_now = sim.robot().base().odom_pose();
    if (out.robots[0].odom) odometry.Add({odom_now, sim.robot().base().odom_covariance(), sim.now()});
    if (out.robots[0].scan && !odometry.empty()) {
      mapping::RangeScan scan{*out.robots[0].scan, sim.robot().laser()->angle_min(), sim.robot().laser()->increment(),
                              sim.now(), world.laser.range_max};
      odom_at_scan = odometry.At(sim.now());
      session.Submit(odom_at_scan, estimate, scan);
      slam_at_scan = session.status().pose;
      if (recorder) {
        const auto& base = sim.robot().base();
        recorder->Laser(sim.now(), world.laser, scan.angle_min, scan.angle_increment, scan.ranges, base.true_pose(),
                        base.odom_pose(), base.odom_twist().vx, base.odom_twist().omega);
      }
    }
    // The SLAM pose of the last scan, carried to now by odometry.
    estimate = slam_at_scan * (odom_at_scan.inverse() * odom_now);
    const Point2 now_true = sim.robot().base().true_pose().translation();
    travelled += Distance(last_true, now_true);
    last_true = now_true;
    if (Distance(visited.back(), estimate.translation()) > 0.5) visited.push_back(estimate.translation());

    // A new goal once a second, on arrival, or when the robot makes no progress for 20 s.
    const double remaining = Distance(estimate.translation(), goal);
    if (remaining < best_remaining - 0.05) {
      best_remaining = remaining;
      last_progress_time = sim.now();
    }
    const bool arrived =
        follower.state() == navigation::FollowerState::kArrived || follower.state() == navigation::FollowerState::kIdle;
    const bool stuck = sim.now() - last_progress_time > 20.0;
    if (sim.now() < look_around_until) continue;
    if (arrived && goals > 0 && look_around_until < 0.0) {
      // Arrived: half a turn on the spot first (the laser sees 240 degrees), then plan again.
      look_around_until = sim.now() + 2.5;
      follower.Clear();
      continue;
    }
    if (sim.now() >= next_plan || (arrived && look_around_until >= 0.0) || stuck) {
      if ((arrived && look_around_until >= 0.0) || stuck)
        eo.excluded.push_back(goal);  // this goal is done or out of reach
      look_around_until = -1.0;
      next_plan = sim.now() + 1.0;
      const auto step = navigation::NextExplorationStep(*session.Map(), estimate, method, visited, eo);
      if (!step) {
        complete = true;
        break;
      }
      if (Distance(step->goal, goal) > 0.3) {
        ++goals;
        best_remaining = 1e9;
        last_progress_time = sim.now();
      }
      goal = step->goal;
      follower.SetPath(step->path, std::nullopt);
    }
    if (sim.now() > 2.0 && static_cast<int>(sim.now() * 100) % 3000 == 0)
      std::fprintf(stderr, "\r  %s: %.0f s simulated, %.1f m driven, %d goals", method_name.c_str(), sim.now(),
                   travelled, goals);
  }
  std::fprintf(stderr, "\n");
  session.Finish();

  // Coverage: the reachable free cells of the truth that the built map shows.
  const auto built = session.Map();
  const mapping::MapCoverage coverage = mapping::CoverageOf(*built, world.map, world.start.translation());
  const mapping::MappingStatus st = session.status();
  std::printf(
      "explore (%s): %s, %.1f%% of the reachable free space mapped (%.1f%% mapped free), %.1f s simulated, "
      "%.1f m driven, %d goals, %d collisions, %d SLAM nodes, %d loop closures\n",
      method_name.c_str(), complete ? "complete" : "stopped at --max-time", 100.0 * coverage.known,
      100.0 * coverage.known_free, sim.now(), travelled, goals, collisions, st.nodes, st.loop_closures);
  if (!png.empty()) SaveMapPng(*built, png);
  if (recorder) recorder->Close();
  return complete ? 0 : 3;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "navd-explore: explore a simulated world from an empty map with navd's SLAM, exploration and path following"};
  std::string world_path, method = "frontier", png, record;
  double max_time = 900.0;
  uint64_t seed = 1;
  app.add_option("--world", world_path, "World YAML or map (default: the embedded warehouse)");
  app.add_option("--method", method, "greedy (seed 002), frontier (Yamauchi) or vfm (book ch. 4 Voronoi Fast Marching)")
      ->check(CLI::IsMember({"greedy", "frontier", "vfm"}));
  app.add_option("--max-time", max_time, "Seconds of simulated time at most")->check(CLI::Range(1.0, 86400.0));
  app.add_option("--png", png, "Write the map built as a PNG");
  app.add_option("--seed", seed, "Simulator seed (sensor and odometry noise)");
  app.add_option("--record", record, "Write the run as a CARMEN log (ROBOTLASER1 at the true pose) to this file");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    const navd::World world = world_path.empty() ? navd::DefaultWorld() : navd::LoadWorldOrMapFile(world_path);
    return Explore(world, navd::navigation::ParseExplorationMethod(method), method, max_time, png, seed, record);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navd-explore: %s\n", e.what());
    return 2;
  }
}
