// navsim: the simulator process. Loads a scenario (or a world file: one robot), steps it at --rate
// times real time, and talks ROS 2-layout DDS: rt/clock and the world's truth globally; per robot
// (rt/<robot>/...) scan, sonar, ir, odom, joint_states, bumper, people, ground_truth and sim/status out,
// cmd_vel and cmd_accel in. Optionally records one robot as a CARMEN log. With --lockstep it steps
// no further than each robot's navd has been given (rt/<robot>/navd/next_tick).
#include <spdlog/cfg/env.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <optional>

#include "dds/participant.h"
#include "dds/participant_flags.h"
#include "services/common/error.h"
#include "services/common/pose_text.h"
#include "services/common/text_file.h"
#include "simulator/carmen_recorder.h"
#include "simulator/lockstep_gate.h"
#include "simulator/robot_topics.h"
#include "simulator/simulation.h"
#include "simulator/step_pacer.h"
#include "simulator/truth_view.h"
#include "simulator/world_topics.h"
#include "view/view_page.h"

namespace {

std::atomic<bool> g_stop{false};
// Wall seconds a lockstep run may fall behind its rate before its schedule starts again from now.
constexpr double kLockstepSlack = 0.05;
void OnSignal(int) { g_stop = true; }

using namespace navd;

struct NavsimOptions {
  std::string scenario_path, world_path, start, ns;
  double rate = 1.0;
  bool fast = false;
  bool lockstep = false;
  double lockstep_timeout = 2.0;  // wall s
  std::optional<uint64_t> seed;
  double duration = 0.0;         // simulated s; 0: until signalled
  double command_timeout = 0.5;  // simulated s
  navd::dds::ParticipantOptions dds;
  std::string network = "loopback";
  std::string view_address = "127.0.0.1:8766", view_port_file;
  bool view_asked = false;
  std::string record_path, record_robot;
  bool no_camera = false;
};

// Fills `o` from the command line; returns the exit code when there is nothing to run (--help, or
// a refused option, whose line CLI11 has printed). Throws std::invalid_argument for a
// --dds-network other than loopback or all.
std::optional<int> ParseOptions(int argc, char** argv, NavsimOptions& o) {
  CLI::App app{
      "navsim: 2-D simulator of wheeled robots with lasers, sonars, IR, encoders and bumpers among moving "
      "obstacles and people, over ROS 2-layout DDS"};
  auto* scenario_opt =
      app.add_option("--scenario", o.scenario_path, "Scenario YAML: world, robots, obstacles, people, seed");
  app.add_option("--world", o.world_path,
                 "World YAML, or a bare map (map_server YAML + PGM, MovingAI .map) with the default robot; one robot "
                 "(default: the embedded warehouse)")
      ->excludes(scenario_opt);
  app.add_option("--start", o.start, "Start pose X,Y[,THETA] of the --world robot (metres, radians, map frame)")
      ->excludes(scenario_opt);
  app.add_option("--rate", o.rate, "Simulated seconds per wall second")->check(CLI::PositiveNumber);
  app.add_flag("--fast", o.fast, "Run as fast as possible (no pacing)");
  app.add_flag(
      "--lockstep", o.lockstep,
      "Step no further than each robot's navd has been given (rt/<robot>/navd/next_tick, navd --use-sim-time): "
      "runs then do not depend on machine load");
  app.add_option("--lockstep-timeout", o.lockstep_timeout,
                 "Wall seconds to wait for a navd before stepping on without it (until it reports again)")
      ->check(CLI::PositiveNumber);
  app.add_option("--seed", o.seed, "Random seed (overrides the scenario's); the same seed repeats the same run");
  navd::dds::AddParticipantFlags(app, o.dds, o.network);
  app.add_option("--namespace", o.ns, "Topic namespace of a --world robot (rt/<ns>/scan ...)")->excludes(scenario_opt);
  app.add_option("--duration", o.duration, "Stop after this many simulated seconds (0: run until signalled)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--command-timeout", o.command_timeout, "Stop a robot after this long without a command, s")
      ->check(CLI::PositiveNumber);
  auto* view_opt = app.add_option("--view", o.view_address,
                                  "Live view of the ground truth HOST:PORT: the Foxglove WebSocket server and the "
                                  "page at http://HOST:PORT/ (port 0 picks a free one); off: none");
  app.add_option("--view-port-file", o.view_port_file, "Write the bound view port to this file");
  app.add_option("--record", o.record_path,
                 "Write a CARMEN log (ROBOTLASER1, ODOM, TRUEPOS) of one robot to this file");
  app.add_option("--record-robot", o.record_robot, "Which robot --record records (default: the first)");
  app.add_flag("--no-camera", o.no_camera,
               "Take every robot's depth camera off (the same run without it, to measure what it is worth)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  o.view_asked = view_opt->count() > 0;
  o.dds.network = navd::dds::ParseNetwork(o.network);
  o.dds.name = "navsim";
  return std::nullopt;
}

// The scenario of --scenario, or of --world (the embedded one by default) with its one robot at
// --start and under --namespace. Throws navd::Error naming the option for a start off the map.
sim::Scenario LoadScenario(const NavsimOptions& o) {
  sim::Scenario scenario;
  if (!o.scenario_path.empty()) {
    scenario = sim::LoadScenarioFile(o.scenario_path);
  } else {
    World world = o.world_path.empty() ? DefaultWorld() : LoadWorldOrMapFile(o.world_path);
    if (!o.start.empty()) {
      const auto p = ParseTuple(o.start, "--start", 2, 3);
      world.start = Pose2{p[0], p[1], p.size() == 3 ? p[2] : 0.0};
      if (!world.start.translation().allFinite() || !std::isfinite(world.start.theta) ||
          !world.map.ContainsPoint(world.start.translation()) ||
          world.map.DiscHitsObstacle(world.start.translation(), world.robot.radius)) {
        throw Error(ErrorCode::kInvalidArgument,
                    "--start '" + o.start + "' puts the robot off the map or inside a wall");
      }
    }
    scenario = sim::ScenarioFromWorld(std::move(world));
    scenario.robots[0].name = o.ns;
  }
  if (o.no_camera)
    for (sim::RobotSpec& r : scenario.robots) r.camera.reset();
  return scenario;
}

// --record: one robot's run as a CARMEN log, written step by step.
class RobotRecording {
 public:
  // Throws navd::Error naming the option for a robot that is not there or has no laser.
  RobotRecording(const NavsimOptions& o, const sim::Simulation& simulation) {
    const auto& robots = simulation.robots();
    bool found = o.record_robot.empty();
    for (size_t i = 0; i < robots.size() && !found; ++i) {
      if (robots[i]->name() == o.record_robot) {
        index_ = i;
        found = true;
      }
    }
    if (!found) throw Error(ErrorCode::kInvalidArgument, "--record-robot: no robot named '" + o.record_robot + "'");
    if (!robots[index_]->laser())
      throw Error(ErrorCode::kInvalidArgument, "--record: the robot has no laser to record");
    recorder_.emplace(o.record_path,
                      "scenario '" + simulation.scenario().name + "', seed " + std::to_string(simulation.seed()));
  }

  void Record(double t, const sim::Simulation& simulation, const sim::StepOutputs& out) {
    const sim::SimulatedRobot& r = *simulation.robots()[index_];
    const sim::MobileBase& base = r.base();
    const sim::RobotReadings& o = out.robots[index_];
    if (o.scan) {
      recorder_->Laser(t, r.laser()->description(), r.laser()->angle_min(), r.laser()->increment(), *o.scan,
                       base.true_pose(), base.odom_pose(), base.odom_twist().vx, base.odom_twist().omega);
    }
    if (o.odom) recorder_->Odometry(t, base.odom_pose(), base.odom_twist().vx, base.odom_twist().omega);
    if (out.truth) recorder_->Truth(t, base.true_pose(), base.odom_pose());
  }

  void Close() { recorder_->Close(); }

 private:
  size_t index_ = 0;
  std::optional<sim::CarmenRecorder> recorder_;
};

// A collision, with where the robot stood: what it was doing when it touched.
void LogCollision(const sim::CollisionEvent& e, const sim::Simulation& simulation) {
  Pose2 at;
  for (const auto& r : simulation.robots())
    if (r->name() == e.robot || (r->name().empty() && e.robot == "robot")) at = r->base().true_pose();
  spdlog::warn(
      "navsim: collision of '{}' at ({:.2f}, {:.2f}, {:.2f}) with {} at ({:.2f}, {:.2f}) t={:.2f}s, the robot "
      "closing at {:.2f} m/s, the other at {:.2f} m/s",
      e.robot, at.x, at.y, at.theta, e.other, e.where.x(), e.where.y(), e.time, e.robot_closing, e.other_closing);
}

void LogStart(const NavsimOptions& o, const sim::Simulation& simulation, bool lockstep) {
  const auto& w = simulation.world();
  spdlog::info(
      "navsim: scenario '{}' on world '{}' ({}x{} cells at {} m), {} robot(s), {} moving obstacle(s), {} "
      "people, {} hidden obstacle(s), rate {}{}, seed {}, DDS domain {} ({})",
      simulation.scenario().name, w.name, w.map.width(), w.map.height(), w.map.resolution(), simulation.robots().size(),
      simulation.moving_obstacles().size(), simulation.people().size(), simulation.scenario().hidden_obstacles,
      o.fast ? std::string("max") : std::to_string(o.rate), lockstep ? " in lockstep with navd" : "", simulation.seed(),
      o.dds.domain, o.network);
  for (const auto& r : simulation.robots()) {
    const Pose2& p = r->base().true_pose();
    spdlog::info("navsim: robot '{}' ({}) at ({:.2f}, {:.2f}, {:.2f}) on rt/{}", simulation.BodyName(r->id()),
                 DriveTypeName(r->spec().body.drive), p.x, p.y, p.theta, r->name().empty() ? "" : r->name() + "/");
  }
}

void LogEnd(const sim::Simulation& simulation, double wall) {
  for (const auto& r : simulation.robots()) {
    spdlog::info("navsim: robot '{}' stopped at t={:.2f}s, travelled {:.2f} m, {} collisions",
                 simulation.BodyName(r->id()), simulation.now(), r->base().distance_travelled(), r->collisions());
  }
  spdlog::info("navsim: {:.1f} simulated seconds in {:.2f} s wall ({:.0f}x real time)", simulation.now(), wall,
               wall > 0 ? simulation.now() / wall : 0.0);
}

// SPDLOG_LEVEL=trace: the ground truth of every step, to set beside navd's trace of its ticks
// when a run goes wrong: each robot's pose and velocity, the moving obstacles, and the people
// within kTracedPeopleRange of a robot.
constexpr double kTracedPeopleRange = 1.5;  // m
void LogGroundTruth(double t, const sim::Simulation& s) {
  std::string line = fmt::format("t={:.2f}s truth:", t);
  for (const auto& r : s.robots()) {
    const Pose2& p = r->base().true_pose();
    const auto& v = r->base().true_twist();
    line += fmt::format(" {} ({:.3f}, {:.3f}, {:.3f}) at {:.2f} m/s {:.2f} rad/s;", s.BodyName(r->id()), p.x, p.y,
                        p.theta, v.vx, v.omega);
  }
  for (const auto& o : s.moving_obstacles())
    line += fmt::format(" {} ({:.3f}, {:.3f}) at ({:.2f}, {:.2f}) m/s;", o.description().name, o.position().x(),
                        o.position().y(), o.velocity().x(), o.velocity().y());
  for (const auto& q : s.people()) {
    bool near = false;
    for (const auto& r : s.robots())
      near = near || Distance(q.position, r->base().true_pose().translation()) < kTracedPeopleRange;
    if (near)
      line += fmt::format(" person {} ({:.3f}, {:.3f}) at ({:.2f}, {:.2f}) m/s;", q.id, q.position.x(), q.position.y(),
                          q.velocity.x(), q.velocity.y());
  }
  spdlog::trace("{}", line);
}

// The truth view of --view, or null for "off". A default address that is taken (another navsim on
// this host) leaves navsim without one, with a warning; an address asked for must bind. Clients
// only watch: navsim takes no commands from its view.
std::unique_ptr<sim::TruthView> StartTruthView(const std::string& address, bool asked, const std::string& port_file,
                                               const sim::Simulation& simulation) {
  if (address == "off") return nullptr;
  navd::view::FoxgloveServerOptions options;
  navd::view::ParseListenAddress("--view", address, options);
  options.access = [](std::string_view) { return navd::view::Access::kWatch; };
  options.name = "navsim (ground truth)";
  options.page = navd::view::ViewPage();
  std::unique_ptr<sim::TruthView> view;
  try {
    view = std::make_unique<sim::TruthView>(options, simulation);
  } catch (const Error& e) {
    if (asked) throw;
    spdlog::warn("navsim: {}; running without the live view (choose another with --view HOST:PORT)", e.what());
    return nullptr;
  }
  if (!port_file.empty()) navd::WriteFileAtomically(port_file, std::to_string(view->port()) + "\n");
  spdlog::info("navsim: ground truth view at http://{}:{}/", options.host, view->port());
  return view;
}

int Run(int argc, char** argv) {
  NavsimOptions o;
  if (const std::optional<int> exit_code = ParseOptions(argc, argv, o)) return *exit_code;
  // SPDLOG_LEVEL=trace (or e.g. "debug"): the log's level, as spdlog reads it (as navd does).
  spdlog::cfg::load_env_levels();

  sim::SimulationOptions options;
  options.seed = o.seed;
  options.command_timeout = o.command_timeout;
  sim::Simulation simulation(LoadScenario(o), options);
  const auto& robots = simulation.robots();
  std::optional<RobotRecording> recording;
  if (!o.record_path.empty()) recording.emplace(o, simulation);

  navd::dds::Participant participant(o.dds);
  sim::WorldTopics world_topics(participant);
  std::unique_ptr<sim::LockstepGate> gate;
  if (o.lockstep) gate = std::make_unique<sim::LockstepGate>(robots.size(), o.lockstep_timeout);
  std::vector<std::unique_ptr<sim::RobotTopics>> topics;
  for (size_t i = 0; i < robots.size(); ++i)
    topics.push_back(std::make_unique<sim::RobotTopics>(participant, *robots[i], gate.get(), i));
  std::unique_ptr<sim::TruthView> view = StartTruthView(o.view_address, o.view_asked, o.view_port_file, simulation);
  LogStart(o, simulation, gate != nullptr);

  // rt/clock at up to 20 x 100 Hz per wall second: enough for sim-time consumers, cheap at 1000x.
  const uint64_t clock_every = o.fast ? 100 : std::max<uint64_t>(1, static_cast<uint64_t>(std::ceil(o.rate / 20.0)));
  sim::StepPacer pacer({simulation.options().physics_step, o.rate, o.fast, gate ? kLockstepSlack : -1.0});
  uint64_t steps = 0;
  bool clock_sent = false;  // rt/clock has carried simulation.now()
  const auto send_clock = [&] {
    world_topics.PublishClock(simulation.now());
    clock_sent = true;
  };
  while (!g_stop && (o.duration <= 0 || simulation.now() < o.duration - 1e-9)) {
    if (gate) {
      // A navd waits for rt/clock to reach its tick: it must have heard the time it is held at.
      if (!clock_sent) send_clock();
      for (const size_t i : gate->WaitUntilAllowed(simulation.now(), send_clock)) {
        spdlog::warn(
            "navsim: robot '{}''s navd sent no next tick for {} s at t={:.2f}s: stepping on without it until "
            "it reports again",
            simulation.BodyName(robots[i]->id()), o.lockstep_timeout, simulation.now());
      }
    }
    for (size_t i = 0; i < topics.size(); ++i) topics[i]->ApplyCommands(simulation, i);
    if (steps % 256 == 0)
      for (size_t i = 0; i < topics.size(); ++i) simulation.SetCameraWatched(i, topics[i]->camera_watched());
    world_topics.ApplyDoorCommands(simulation);
    const sim::StepOutputs out = simulation.Step();
    ++steps;
    const double t = simulation.now();
    clock_sent = false;
    const double wall = pacer.WallSeconds();
    for (size_t i = 0; i < robots.size(); ++i) {
      topics[i]->Publish(t, *robots[i], out.robots[i], out.truth, out.status, wall > 0 ? t / wall : 0.0);
    }
    // After the sensors, so that a sim-time consumer woken by the clock finds this step's readings.
    if (steps % clock_every == 0) send_clock();
    if (out.truth) world_topics.PublishWorldState(t, simulation);
    if (view) view->Update(simulation);
    if (spdlog::should_log(spdlog::level::trace)) LogGroundTruth(t, simulation);
    for (const sim::CollisionEvent& e : out.events) {
      LogCollision(e, simulation);
      world_topics.PublishCollision(e);
    }
    if (recording) recording->Record(t, simulation, out);
    pacer.AfterStep();
  }
  if (recording) recording->Close();
  LogEnd(simulation, pacer.WallSeconds());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navsim: %s\n", e.what());
    return 2;
  }
}
