// navsim: the simulator process. Loads a scenario (or a world file: one robot), steps it at --rate
// times real time, and talks ROS 2-layout DDS: rt/clock and the world's truth globally; per robot
// (rt/<robot>/...) scan, sonar, ir, odom, joint_states, bumper, people, ground_truth and sim/status out,
// cmd_vel and cmd_accel in. Optionally records one robot as a CARMEN log. With --lockstep it steps
// no further than each robot's navd has been given (rt/<robot>/navd/next_tick).
#include <spdlog/cfg/env.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <mutex>
#include <thread>

#include "dds/conversions.h"
#include "dds/participant.h"
#include "dds/point_cloud2.h"
#include "dds/topics.h"
#include "geometry_msgsPubSubTypes.h"
#include "nav_msgsPubSubTypes.h"
#include "navsim_msgsPubSubTypes.h"
#include "people_msgsPubSubTypes.h"
#include "rosgraph_msgsPubSubTypes.h"
#include "sensor_msgsPubSubTypes.h"
#include "services/common/error.h"
#include "services/common/pose_text.h"
#include "services/common/text_file.h"
#include "simulator/carmen_recorder.h"
#include "simulator/lockstep_gate.h"
#include "simulator/simulation.h"
#include "simulator/truth_view.h"
#include "view/view_page.h"

namespace {

std::atomic<bool> g_stop{false};
// Wall seconds a lockstep run may fall behind its rate before its schedule starts again from now.
constexpr double kLockstepSlack = 0.05;
void OnSignal(int) { g_stop = true; }

using namespace navd;
namespace msgs_geo = geometry_msgs::msg::dds_;
namespace msgs_sim = navsim_msgs::msg::dds_;
namespace msgs_sensor = sensor_msgs::msg::dds_;
using navd::dds::Reliability;
using navd::dds::TopicName;

using navd::dds::MakeHeader;

nav_msgs::msg::dds_::Odometry_ MakeOdometry(double t, const Pose2& pose, const sim::BodyTwist& twist,
                                            const Eigen::Matrix3d& cov, const std::string& frame) {
  return navd::dds::MakeOdometry(t, pose, twist.vx, twist.vy, twist.omega, cov, frame);
}

// One robot's DDS endpoints. Commands arrive on DDS threads and wait in `pending` until the
// simulation thread applies them between steps.
class RobotTopics {
 public:
  // gate: when given (--lockstep), the robot's navd/next_tick reports go to it as robot `index`.
  RobotTopics(navd::dds::Participant& p, const sim::SimulatedRobot& robot, sim::LockstepGate* gate, size_t index)
      : ns_(robot.name()),
        scan_(p, TopicName(ns_, navd::dds::kScan), Reliability::kBestEffort, 5),
        sonar_(p, TopicName(ns_, navd::dds::kSonar), Reliability::kBestEffort, 32),
        ir_(p, TopicName(ns_, navd::dds::kIr), Reliability::kBestEffort, 8),
        odom_(p, TopicName(ns_, navd::dds::kOdom), Reliability::kBestEffort, 5),
        joints_(p, TopicName(ns_, navd::dds::kJointStates), Reliability::kBestEffort, 5),
        bumper_(p, TopicName(ns_, navd::dds::kBumper), Reliability::kBestEffort, 5),
        truth_(p, TopicName(ns_, navd::dds::kGroundTruth), Reliability::kBestEffort, 5),
        status_(p, TopicName(ns_, navd::dds::kSimStatus), Reliability::kReliable, 10),
        cmd_vel_(
            p, TopicName(ns_, navd::dds::kCmdVel), Reliability::kReliable,
            [this](const msgs_geo::Twist_& m) {
              if (!std::isfinite(m.linear().x()) || !std::isfinite(m.linear().y()) || !std::isfinite(m.angular().z())) {
                spdlog::warn("navsim: ignored a {} with non-finite values", TopicName(ns_, navd::dds::kCmdVel));
                return;
              }
              std::lock_guard<std::mutex> lock(mutex_);
              velocity_ = sim::BodyTwist{m.linear().x(), m.linear().y(), m.angular().z()};
              accel_.reset();
            }),
        cmd_accel_(p, TopicName(ns_, navd::dds::kCmdAccel), Reliability::kReliable, [this](const msgs_geo::Accel_& m) {
          if (!std::isfinite(m.linear().x()) || !std::isfinite(m.angular().z())) {
            spdlog::warn("navsim: ignored a {} with non-finite values", TopicName(ns_, navd::dds::kCmdAccel));
            return;
          }
          std::lock_guard<std::mutex> lock(mutex_);
          accel_ = std::make_pair(m.linear().x(), m.angular().z());
          velocity_.reset();
        }) {
    if (const auto& l = robot.laser()) {
      scan_msg_.angle_min(static_cast<float>(l->angle_min()));
      scan_msg_.angle_max(static_cast<float>(l->angle_max()));
      scan_msg_.angle_increment(static_cast<float>(l->increment()));
      scan_msg_.scan_time(static_cast<float>(1.0 / l->description().rate));
      scan_msg_.time_increment(static_cast<float>(1.0 / l->description().rate / l->description().beams));
      scan_msg_.range_min(static_cast<float>(l->description().range_min));
      scan_msg_.range_max(static_cast<float>(l->description().range_max));
    }
    if (robot.spec().camera) {
      camera_ = std::make_unique<navd::dds::Writer<msgs_sensor::PointCloud2_PubSubType>>(
          p, TopicName(ns_, navd::dds::kCameraPoints), Reliability::kBestEffort, 2, /*large=*/true);
    }
    if (robot.spec().people) {
      people_ = std::make_unique<navd::dds::Writer<people_msgs::msg::dds_::People_PubSubType>>(
          p, TopicName(ns_, navd::dds::kPeople), Reliability::kBestEffort, 2);
    }
    if (gate) {
      next_tick_ = std::make_unique<navd::dds::Reader<rosgraph_msgs::msg::dds_::Clock_PubSubType>>(
          p, TopicName(ns_, navd::dds::kNextTick), Reliability::kReliable,
          [gate, index](const rosgraph_msgs::msg::dds_::Clock_& m) {
            gate->Report(index, navd::dds::FromTime(m.clock()));
          },
          1);
    }
  }

  // Whether a reader takes this robot's depth images (asked of DDS every few hundred steps).
  bool camera_watched() const { return camera_ && camera_->matched() > 0; }

  void ApplyCommands(sim::Simulation& simulation, size_t index) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (velocity_) simulation.Command(index, *velocity_);
    if (accel_) simulation.CommandAcceleration(index, accel_->first, accel_->second);
    velocity_.reset();
    accel_.reset();
  }

  void Publish(double t, const sim::SimulatedRobot& robot, const sim::RobotReadings& in, bool truth, bool status,
               double real_time_factor) {
    const auto& base = robot.base();
    // Odometry first: a reader pairs each scan with the odometry of its instant, and waits for it.
    if (in.odom) odom_.Write(MakeOdometry(t, base.odom_pose(), base.odom_twist(), base.odom_covariance(), "odom"));
    if (in.scan) {
      scan_msg_.header(MakeHeader(t, "base_scan"));
      scan_msg_.ranges(*in.scan);
      scan_.Write(scan_msg_);
    }
    if (in.camera && camera_) camera_->Write(navd::dds::EncodeXyzCloud(*in.camera, t, "camera_depth_optical_frame"));
    if (in.sonar) PublishRanges(t, "sonar", 0, *robot.sonar(), *in.sonar, sonar_);
    if (in.ir) PublishRanges(t, "ir", 1, *robot.ir(), *in.ir, ir_);
    if (in.people && people_) {
      people_msgs::msg::dds_::People_ m;
      m.header(MakeHeader(t, "base_link"));
      for (const sim::PersonReading& r : *in.people) {
        people_msgs::msg::dds_::Person_ person;
        person.name("person " + std::to_string(r.id));
        person.position().x(r.position.x());
        person.position().y(r.position.y());
        person.velocity().x(r.velocity.x());
        person.velocity().y(r.velocity.y());
        person.reliability(1.0);
        m.people().push_back(std::move(person));
      }
      people_->Write(m);
    }
    if (in.encoders) {
      msgs_sensor::JointState_ j;
      j.header(MakeHeader(t, "base_link"));
      const auto angles = base.wheel_angles();
      const auto speeds = base.wheel_speeds();
      for (size_t i = 0; i < angles.size(); ++i) {
        j.name().push_back(angles.size() == 2 ? (i == 0 ? "left_wheel" : "right_wheel")
                                              : "wheel_" + std::to_string(i + 1));
        j.position().push_back(angles[i]);
        j.velocity().push_back(speeds[i] / base.description().wheel_radius);
      }
      joints_.Write(j);
    }
    if (in.bumper) {
      msgs_sim::BumperState_ b;
      b.header(MakeHeader(t, "base_link"));
      b.front(robot.bumper().front);
      b.rear(robot.bumper().rear);
      bumper_.Write(b);
    }
    if (truth) truth_.Write(MakeOdometry(t, base.true_pose(), base.true_twist(), Eigen::Matrix3d::Zero(), "map"));
    if (status || robot.collisions() != reported_collisions_) {
      msgs_sim::SimStatus_ s;
      s.header(MakeHeader(t, "map"));
      s.x(base.true_pose().x);
      s.y(base.true_pose().y);
      s.theta(base.true_pose().theta);
      s.collisions(robot.collisions());
      s.in_collision(robot.in_collision());
      s.distance_travelled(base.distance_travelled());
      s.real_time_factor(real_time_factor);
      status_.Write(s);
      reported_collisions_ = robot.collisions();
    }
  }

 private:
  template <typename WriterT>
  void PublishRanges(double t, const std::string& kind, uint8_t radiation, const sim::RangeSensorArray& array,
                     const std::vector<float>& ranges, WriterT& writer) {
    const auto& d = array.description();
    for (size_t i = 0; i < ranges.size(); ++i) {
      msgs_sensor::Range_ r;
      r.header(MakeHeader(t, kind + "_" + std::to_string(i)));
      r.radiation_type(radiation);
      r.field_of_view(static_cast<float>(d.cone));
      r.min_range(static_cast<float>(d.range_min));
      r.max_range(static_cast<float>(d.range_max));
      r.range(ranges[i]);
      writer.Write(r);
    }
  }

  std::string ns_;
  navd::dds::Writer<msgs_sensor::LaserScan_PubSubType> scan_;
  navd::dds::Writer<msgs_sensor::Range_PubSubType> sonar_, ir_;
  navd::dds::Writer<nav_msgs::msg::dds_::Odometry_PubSubType> odom_;
  navd::dds::Writer<msgs_sensor::JointState_PubSubType> joints_;
  navd::dds::Writer<msgs_sim::BumperState_PubSubType> bumper_;
  navd::dds::Writer<nav_msgs::msg::dds_::Odometry_PubSubType> truth_;
  navd::dds::Writer<msgs_sim::SimStatus_PubSubType> status_;
  std::unique_ptr<navd::dds::Writer<people_msgs::msg::dds_::People_PubSubType>> people_;  // with a people sensor
  std::unique_ptr<navd::dds::Writer<msgs_sensor::PointCloud2_PubSubType>> camera_;        // with a depth camera
  std::mutex mutex_;
  std::optional<sim::BodyTwist> velocity_;
  std::optional<std::pair<double, double>> accel_;
  navd::dds::Reader<msgs_geo::Twist_PubSubType> cmd_vel_;
  navd::dds::Reader<msgs_geo::Accel_PubSubType> cmd_accel_;
  std::unique_ptr<navd::dds::Reader<rosgraph_msgs::msg::dds_::Clock_PubSubType>> next_tick_;
  msgs_sensor::LaserScan_ scan_msg_;
  uint32_t reported_collisions_ = 0;
};

msgs_sim::WorldState_ MakeWorldState(double t, const sim::Simulation& s) {
  msgs_sim::WorldState_ w;
  w.header(MakeHeader(t, "map"));
  auto add = [&](const std::string& name, const char* kind, const Pose2& pose, const Point2& v, double radius) {
    msgs_sim::Body_ b;
    b.name(name);
    b.kind(kind);
    b.x(pose.x);
    b.y(pose.y);
    b.theta(pose.theta);
    b.vx(v.x());
    b.vy(v.y());
    b.radius(radius);
    w.bodies().push_back(b);
  };
  for (const auto& r : s.robots()) {
    const Pose2& p = r->base().true_pose();
    const auto tw = r->base().true_twist();
    const double c = std::cos(p.theta), sn = std::sin(p.theta);
    add(s.BodyName(r->id()), "robot", p, {c * tw.vx - sn * tw.vy, sn * tw.vx + c * tw.vy}, r->spec().body.radius);
  }
  for (const auto& o : s.moving_obstacles()) {
    add(o.description().name, "obstacle",
        {o.position().x(), o.position().y(), std::atan2(o.velocity().y(), o.velocity().x())}, o.velocity(),
        o.description().radius);
  }
  for (const auto& p : s.people()) {
    add("person " + std::to_string(p.id), "person",
        {p.position.x(), p.position.y(), std::atan2(p.velocity.y(), p.velocity.x())}, p.velocity,
        s.scenario().crowd->radius);
  }
  for (const auto& d : s.scenario().doors) {
    msgs_sim::DoorState_ door;
    door.name(d.name);
    door.closed(d.closed);
    w.doors().push_back(door);
  }
  return w;
}

// Door commands arrive on a DDS thread and are applied between steps.
class DoorCommands {
 public:
  explicit DoorCommands(navd::dds::Participant& p)
      : reader_(p, navd::dds::kDoorCommand, navd::dds::Reliability::kReliable, [this](const msgs_sim::DoorCommand_& m) {
          std::lock_guard<std::mutex> lock(mutex_);
          pending_.emplace_back(m.name(), m.closed());
        }) {}

  void Apply(sim::Simulation& simulation) {
    std::vector<std::pair<std::string, bool>> pending;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      pending.swap(pending_);
    }
    for (const auto& [name, closed] : pending) {
      try {
        simulation.SetDoor(name, closed);
        spdlog::info("navsim: door '{}' {} at t={:.2f}s", name, closed ? "closed" : "opened", simulation.now());
      } catch (const Error& e) {
        spdlog::warn("navsim: ignored {} command: {}", navd::dds::kDoorCommand, e.what());
      }
    }
  }

 private:
  std::mutex mutex_;
  std::vector<std::pair<std::string, bool>> pending_;
  navd::dds::Reader<msgs_sim::DoorCommand_PubSubType> reader_;
};

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
  CLI::App app{
      "navsim: 2-D simulator of wheeled robots with lasers, sonars, IR, encoders and bumpers among moving "
      "obstacles and people, over ROS 2-layout DDS"};
  std::string scenario_path, world_path, network = "loopback", ns, record_path, record_robot, start;
  double rate = 1.0;
  std::optional<uint64_t> seed;
  int domain = 0;
  double duration = 0.0;
  bool fast = false;
  auto* scenario_opt =
      app.add_option("--scenario", scenario_path, "Scenario YAML: world, robots, obstacles, people, seed");
  app.add_option("--world", world_path,
                 "World YAML, or a bare map (map_server YAML + PGM, MovingAI .map) with the default robot; one robot "
                 "(default: the embedded warehouse)")
      ->excludes(scenario_opt);
  app.add_option("--start", start, "Start pose X,Y[,THETA] of the --world robot (metres, radians, map frame)")
      ->excludes(scenario_opt);
  app.add_option("--rate", rate, "Simulated seconds per wall second")->check(CLI::PositiveNumber);
  app.add_flag("--fast", fast, "Run as fast as possible (no pacing)");
  bool lockstep = false;
  double lockstep_timeout = 2.0;
  app.add_flag(
      "--lockstep", lockstep,
      "Step no further than each robot's navd has been given (rt/<robot>/navd/next_tick, navd --use-sim-time): "
      "runs then do not depend on machine load");
  app.add_option("--lockstep-timeout", lockstep_timeout,
                 "Wall seconds to wait for a navd before stepping on without it (until it reports again)")
      ->check(CLI::PositiveNumber);
  app.add_option("--seed", seed, "Random seed (overrides the scenario's); the same seed repeats the same run");
  app.add_option("--domain", domain, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--dds-network", network, "loopback (default: 127.0.0.1 only) or all (every interface)");
  std::string dds_security, discovery_server;
  std::vector<std::string> dds_peers;
  app.add_option("--dds-peer", dds_peers, "Extra unicast DDS discovery peer (IPv4), repeatable");
  app.add_option("--dds-discovery-server", discovery_server,
                 "HOST:PORT of a Fast DDS discovery server (fast-discovery-server -i 0): discover peers through it "
                 "by unicast, as in a cluster without multicast");
  app.add_option("--dds-security", dds_security,
                 "DDS Security enclave directory (cert.pem, key.pem, CAs, signed governance and permissions; "
                 "scripts/make-keystore makes one): authenticated, access-controlled, encrypted DDS");
  app.add_option("--namespace", ns, "Topic namespace of a --world robot (rt/<ns>/scan ...)")->excludes(scenario_opt);
  app.add_option("--duration", duration, "Stop after this many simulated seconds (0: run until signalled)")
      ->check(CLI::NonNegativeNumber);
  double command_timeout = 0.5;
  app.add_option("--command-timeout", command_timeout, "Stop a robot after this long without a command, s")
      ->check(CLI::PositiveNumber);
  std::string view_address = "127.0.0.1:8766", view_port_file;
  auto* view_opt = app.add_option("--view", view_address,
                                  "Live view of the ground truth HOST:PORT: the Foxglove WebSocket server and the "
                                  "page at http://HOST:PORT/ (port 0 picks a free one); off: none");
  app.add_option("--view-port-file", view_port_file, "Write the bound view port to this file");
  app.add_option("--record", record_path, "Write a CARMEN log (ROBOTLASER1, ODOM, TRUEPOS) of one robot to this file");
  app.add_option("--record-robot", record_robot, "Which robot --record records (default: the first)");
  bool no_camera = false;
  app.add_flag("--no-camera", no_camera,
               "Take every robot's depth camera off (the same run without it, to measure what it is worth)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  // SPDLOG_LEVEL=trace (or e.g. "debug"): the log's level, as spdlog reads it (as navd does).
  spdlog::cfg::load_env_levels();

  sim::Scenario scenario;
  if (!scenario_path.empty()) {
    scenario = sim::LoadScenarioFile(scenario_path);
  } else {
    World world = world_path.empty() ? DefaultWorld() : LoadWorldOrMapFile(world_path);
    if (!start.empty()) {
      const auto p = ParseTuple(start, "--start", 2, 3);
      world.start = Pose2{p[0], p[1], p.size() == 3 ? p[2] : 0.0};
      if (!world.start.translation().allFinite() || !std::isfinite(world.start.theta) ||
          !world.map.ContainsPoint(world.start.translation()) ||
          world.map.DiscHitsObstacle(world.start.translation(), world.robot.radius)) {
        throw Error(ErrorCode::kInvalidArgument, "--start '" + start + "' puts the robot off the map or inside a wall");
      }
    }
    scenario = sim::ScenarioFromWorld(std::move(world));
    scenario.robots[0].name = ns;
  }
  if (no_camera)
    for (sim::RobotSpec& r : scenario.robots) r.camera.reset();
  sim::SimulationOptions options;
  options.seed = seed;
  options.command_timeout = command_timeout;
  sim::Simulation simulation(std::move(scenario), options);
  const auto& robots = simulation.robots();

  size_t recorded = 0;
  std::unique_ptr<sim::CarmenRecorder> recorder;
  if (!record_path.empty()) {
    bool found = record_robot.empty();
    for (size_t i = 0; i < robots.size() && !found; ++i) {
      if (robots[i]->name() == record_robot) {
        recorded = i;
        found = true;
      }
    }
    if (!found) throw Error(ErrorCode::kInvalidArgument, "--record-robot: no robot named '" + record_robot + "'");
    if (!robots[recorded]->laser())
      throw Error(ErrorCode::kInvalidArgument, "--record: the robot has no laser to record");
    recorder = std::make_unique<sim::CarmenRecorder>(
        record_path, "scenario '" + simulation.scenario().name + "', seed " + std::to_string(simulation.seed()));
  }

  navd::dds::ParticipantOptions dds_options;
  dds_options.domain = domain;
  dds_options.network = navd::dds::ParseNetwork(network);
  dds_options.name = "navsim";
  dds_options.security_enclave = dds_security;
  dds_options.discovery_server = discovery_server;
  dds_options.peers = dds_peers;
  navd::dds::Participant participant(dds_options);
  navd::dds::Writer<rosgraph_msgs::msg::dds_::Clock_PubSubType> clock_writer(participant, navd::dds::kClock,
                                                                             Reliability::kBestEffort, 1);
  navd::dds::Writer<msgs_sim::WorldState_PubSubType> world_writer(participant, navd::dds::kWorldState,
                                                                  Reliability::kBestEffort, 2);
  navd::dds::Writer<msgs_sim::CollisionEvent_PubSubType> collision_writer(participant, navd::dds::kCollisions,
                                                                          Reliability::kReliable, 100);
  std::unique_ptr<sim::LockstepGate> gate;
  if (lockstep) gate = std::make_unique<sim::LockstepGate>(robots.size(), lockstep_timeout);
  std::vector<std::unique_ptr<RobotTopics>> topics;
  for (size_t i = 0; i < robots.size(); ++i)
    topics.push_back(std::make_unique<RobotTopics>(participant, *robots[i], gate.get(), i));
  DoorCommands doors(participant);

  std::unique_ptr<sim::TruthView> view =
      StartTruthView(view_address, view_opt->count() > 0, view_port_file, simulation);

  const auto& w = simulation.world();
  spdlog::info(
      "navsim: scenario '{}' on world '{}' ({}x{} cells at {} m), {} robot(s), {} moving obstacle(s), {} "
      "people, {} hidden obstacle(s), rate {}{}, seed {}, DDS domain {} ({})",
      simulation.scenario().name, w.name, w.map.width(), w.map.height(), w.map.resolution(), robots.size(),
      simulation.moving_obstacles().size(), simulation.people().size(), simulation.scenario().hidden_obstacles,
      fast ? std::string("max") : std::to_string(rate), gate ? " in lockstep with navd" : "", simulation.seed(), domain,
      network);
  for (const auto& r : robots) {
    const Pose2& p = r->base().true_pose();
    spdlog::info("navsim: robot '{}' ({}) at ({:.2f}, {:.2f}, {:.2f}) on rt/{}", simulation.BodyName(r->id()),
                 DriveTypeName(r->spec().body.drive), p.x, p.y, p.theta, r->name().empty() ? "" : r->name() + "/");
  }

  const double dt = simulation.options().physics_step;
  // rt/clock at up to 20 x 100 Hz per wall second: enough for sim-time consumers, cheap at 1000x.
  const uint64_t clock_every = fast ? 100 : std::max<uint64_t>(1, static_cast<uint64_t>(std::ceil(rate / 20.0)));
  const auto wall_start = std::chrono::steady_clock::now();
  // Pacing counts from here; under lockstep a slow navd moves it on, so that the simulation does
  // not then race to catch up with the wall clock.
  auto schedule_start = wall_start;
  uint64_t steps = 0, scheduled_steps = 0;
  bool clock_sent = false;  // rt/clock has carried simulation.now()
  const auto send_clock = [&] {
    rosgraph_msgs::msg::dds_::Clock_ clock;
    clock.clock(navd::dds::ToTime(simulation.now()));
    clock_writer.Write(clock);
    clock_sent = true;
  };
  while (!g_stop && (duration <= 0 || simulation.now() < duration - 1e-9)) {
    if (gate) {
      // A navd waits for rt/clock to reach its tick: it must have heard the time it is held at.
      if (!clock_sent) send_clock();
      for (const size_t i : gate->WaitUntilAllowed(simulation.now(), send_clock)) {
        spdlog::warn(
            "navsim: robot '{}''s navd sent no next tick for {} s at t={:.2f}s: stepping on without it until "
            "it reports again",
            simulation.BodyName(robots[i]->id()), lockstep_timeout, simulation.now());
      }
    }
    for (size_t i = 0; i < topics.size(); ++i) topics[i]->ApplyCommands(simulation, i);
    if (steps % 256 == 0)
      for (size_t i = 0; i < topics.size(); ++i) simulation.SetCameraWatched(i, topics[i]->camera_watched());
    doors.Apply(simulation);
    const sim::StepOutputs out = simulation.Step();
    ++steps;
    const double t = simulation.now();
    ++scheduled_steps;
    clock_sent = false;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    for (size_t i = 0; i < robots.size(); ++i) {
      topics[i]->Publish(t, *robots[i], out.robots[i], out.truth, out.status, wall > 0 ? t / wall : 0.0);
    }
    // After the sensors, so that a sim-time consumer woken by the clock finds this step's readings.
    if (steps % clock_every == 0) send_clock();
    if (out.truth) world_writer.Write(MakeWorldState(t, simulation));
    if (view) view->Update(simulation);
    if (spdlog::should_log(spdlog::level::trace)) LogGroundTruth(t, simulation);
    for (const auto& e : out.events) {
      // Where the robot stood, too: what it was doing when it touched.
      Pose2 at;
      for (const auto& r : robots)
        if (r->name() == e.robot || (r->name().empty() && e.robot == "robot")) at = r->base().true_pose();
      spdlog::warn(
          "navsim: collision of '{}' at ({:.2f}, {:.2f}, {:.2f}) with {} at ({:.2f}, {:.2f}) t={:.2f}s, the robot "
          "closing at {:.2f} m/s, the other at {:.2f} m/s",
          e.robot, at.x, at.y, at.theta, e.other, e.where.x(), e.where.y(), e.time, e.robot_closing, e.other_closing);
      msgs_sim::CollisionEvent_ m;
      m.header(MakeHeader(e.time, "map"));
      m.robot(e.robot);
      m.other(e.other);
      m.x(e.where.x());
      m.y(e.where.y());
      collision_writer.Write(m);
    }
    if (recorder) {
      const auto& r = *robots[recorded];
      const auto& base = r.base();
      const auto& o = out.robots[recorded];
      if (o.scan) {
        recorder->Laser(t, r.laser()->description(), r.laser()->angle_min(), r.laser()->increment(), *o.scan,
                        base.true_pose(), base.odom_pose(), base.odom_twist().vx, base.odom_twist().omega);
      }
      if (o.odom) recorder->Odometry(t, base.odom_pose(), base.odom_twist().vx, base.odom_twist().omega);
      if (out.truth) recorder->Truth(t, base.true_pose(), base.odom_pose());
    }
    // Pace to `rate` times real time; sleeping only when ahead keeps long runs on schedule.
    if (!fast) {
      const auto now = std::chrono::steady_clock::now();
      const double ahead = scheduled_steps * dt / rate - std::chrono::duration<double>(now - schedule_start).count();
      if (ahead > 0) {
        std::this_thread::sleep_for(std::chrono::duration<double>(ahead));
      } else if (gate && ahead < -kLockstepSlack) {
        schedule_start = now;
        scheduled_steps = 0;
      }
    }
  }
  if (recorder) recorder->Close();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  for (const auto& r : robots) {
    spdlog::info("navsim: robot '{}' stopped at t={:.2f}s, travelled {:.2f} m, {} collisions",
                 simulation.BodyName(r->id()), simulation.now(), r->base().distance_travelled(), r->collisions());
  }
  spdlog::info("navsim: {:.1f} simulated seconds in {:.2f} s wall ({:.0f}x real time)", simulation.now(), wall,
               wall > 0 ? simulation.now() / wall : 0.0);
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
