// navsim: the simulated robot process. Loads a world, steps it at --rate times real time, and
// talks ROS 2-layout DDS: publishes rt/clock, rt/scan, rt/odom, rt/ground_truth and
// rt/sim/status, subscribes rt/cmd_vel.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <thread>

#include "dds/conversions.h"
#include "dds/participant.h"
#include "dds/topics.h"
#include "geometry_msgsPubSubTypes.h"
#include "nav_msgsPubSubTypes.h"
#include "navsim_msgsPubSubTypes.h"
#include "rosgraph_msgsPubSubTypes.h"
#include "sensor_msgsPubSubTypes.h"
#include "services/common/error.h"
#include "simulator/simulation.h"

namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop = true; }

using namespace navd;
namespace msgs_geo = geometry_msgs::msg::dds_;

std_msgs::msg::dds_::Header_ Header(double t, const std::string& frame) {
  std_msgs::msg::dds_::Header_ h;
  h.stamp(navd::dds::ToTime(t));
  h.frame_id(frame);
  return h;
}

void FillCovariance(const Eigen::Matrix3d& c, std::array<double, 36>& out) {
  // ROS order (x, y, z, roll, pitch, yaw): our (x, y, theta) sit at indices 0, 1, 5.
  const int idx[3] = {0, 1, 5};
  out.fill(0.0);
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) out[idx[r] * 6 + idx[k]] = c(r, k);
}

nav_msgs::msg::dds_::Odometry_ MakeOdometry(double t, const Pose2& pose, const Twist2& twist,
                                             const Eigen::Matrix3d& cov, const std::string& frame) {
  nav_msgs::msg::dds_::Odometry_ m;
  m.header(Header(t, frame));
  m.child_frame_id("base_link");
  m.pose().pose(navd::dds::ToPose(pose));
  FillCovariance(cov, m.pose().covariance());
  m.twist().twist().linear().x(twist.v);
  m.twist().twist().angular().z(twist.omega);
  return m;
}

int Run(int argc, char** argv) {
  CLI::App app{"navsim: 2-D simulator of a differential-drive robot with a laser, over ROS 2-layout DDS"};
  std::string world_path, network = "loopback", ns;
  double rate = 1.0;
  uint64_t seed = 1;
  int domain = 0;
  double duration = 0.0;
  app.add_option("--world", world_path, "World YAML (default: the embedded warehouse)");
  app.add_option("--rate", rate, "Simulated seconds per wall second")->check(CLI::PositiveNumber);
  app.add_option("--seed", seed, "Random seed; the same seed repeats the same noise");
  app.add_option("--domain", domain, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--dds-network", network, "loopback (default: 127.0.0.1 only) or all (every interface)");
  app.add_option("--namespace", ns, "Robot namespace for topics (rt/<ns>/scan ...)");
  app.add_option("--duration", duration, "Stop after this many simulated seconds (0: run until signalled)");
  double command_timeout = 0.5;
  app.add_option("--command-timeout", command_timeout, "Stop the robot after this long without cmd_vel, s")
      ->check(CLI::PositiveNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  World world = world_path.empty() ? DefaultWorld() : LoadWorldFile(world_path);
  sim::SimulationOptions options;
  options.seed = seed;
  options.command_timeout = command_timeout;
  sim::Simulation simulation(std::move(world), options);
  const auto& w = simulation.world();

  navd::dds::ParticipantOptions dds_options;
  dds_options.domain = domain;
  dds_options.network = navd::dds::ParseNetwork(network);
  dds_options.name = "navsim";
  navd::dds::Participant participant(dds_options);
  using navd::dds::Reliability;
  navd::dds::Writer<rosgraph_msgs::msg::dds_::Clock_PubSubType> clock_writer(participant, navd::dds::kClock,
                                                                        Reliability::kBestEffort, 1);
  navd::dds::Writer<sensor_msgs::msg::dds_::LaserScan_PubSubType> scan_writer(
      participant, navd::dds::TopicName(ns, navd::dds::kScan), Reliability::kBestEffort, 5);
  navd::dds::Writer<nav_msgs::msg::dds_::Odometry_PubSubType> odom_writer(participant, navd::dds::TopicName(ns, navd::dds::kOdom),
                                                                     Reliability::kBestEffort, 5);
  navd::dds::Writer<nav_msgs::msg::dds_::Odometry_PubSubType> truth_writer(
      participant, navd::dds::TopicName(ns, navd::dds::kGroundTruth), Reliability::kBestEffort, 5);
  navd::dds::Writer<navsim_msgs::msg::dds_::SimStatus_PubSubType> status_writer(
      participant, navd::dds::TopicName(ns, navd::dds::kSimStatus), Reliability::kReliable, 10);

  // Commands cross threads through this slot; the simulation thread applies them.
  std::mutex cmd_mutex;
  std::optional<Twist2> pending;
  navd::dds::Reader<msgs_geo::Twist_PubSubType> cmd_reader(
      participant, navd::dds::TopicName(ns, navd::dds::kCmdVel), Reliability::kReliable, [&](const msgs_geo::Twist_& m) {
        if (!std::isfinite(m.linear().x()) || !std::isfinite(m.angular().z())) {
          spdlog::warn("navsim: ignored a cmd_vel with non-finite values");
          return;
        }
        std::lock_guard<std::mutex> lock(cmd_mutex);
        pending = Twist2{m.linear().x(), m.angular().z()};
      });

  spdlog::info("navsim: world '{}' ({}x{} cells at {} m), robot at ({:.2f}, {:.2f}, {:.2f}), rate {}x, seed {}, "
               "DDS domain {} ({})",
               w.name, w.map.width(), w.map.height(), w.map.resolution(), w.start.x, w.start.y, w.start.theta, rate,
               seed, domain, network);

  sensor_msgs::msg::dds_::LaserScan_ scan;
  scan.angle_min(static_cast<float>(simulation.laser().angle_min()));
  scan.angle_max(static_cast<float>(simulation.laser().angle_max()));
  scan.angle_increment(static_cast<float>(simulation.laser().increment()));
  scan.scan_time(static_cast<float>(1.0 / w.laser.rate));
  scan.time_increment(static_cast<float>(1.0 / w.laser.rate / w.laser.beams));
  scan.range_min(static_cast<float>(w.laser.range_min));
  scan.range_max(static_cast<float>(w.laser.range_max));

  const double dt = simulation.options().physics_step;
  const auto wall_start = std::chrono::steady_clock::now();
  uint32_t reported_collisions = 0;
  uint64_t steps = 0;
  while (!g_stop && (duration <= 0 || simulation.now() < duration)) {
    {
      std::lock_guard<std::mutex> lock(cmd_mutex);
      if (pending) simulation.Command(*pending);
      pending.reset();
    }
    const sim::StepOutputs out = simulation.Step();
    ++steps;
    const double t = simulation.now();
    const auto& robot = simulation.robot();

    rosgraph_msgs::msg::dds_::Clock_ clock;
    clock.clock(navd::dds::ToTime(t));
    clock_writer.Write(clock);
    if (out.scan) {
      scan.header(Header(t, "base_scan"));
      scan.ranges(*out.scan);
      scan_writer.Write(scan);
    }
    if (out.odom) {
      odom_writer.Write(MakeOdometry(t, robot.odom_pose(), robot.odom_twist(), robot.odom_covariance(), "odom"));
    }
    if (out.truth) {
      truth_writer.Write(MakeOdometry(t, robot.true_pose(), robot.true_twist(), Eigen::Matrix3d::Zero(), "map"));
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    if (out.status || robot.collisions() != reported_collisions) {
      navsim_msgs::msg::dds_::SimStatus_ s;
      s.header(Header(t, "map"));
      s.x(robot.true_pose().x);
      s.y(robot.true_pose().y);
      s.theta(robot.true_pose().theta);
      s.collisions(robot.collisions());
      s.in_collision(robot.in_collision());
      s.distance_travelled(robot.distance_travelled());
      s.real_time_factor(wall > 0 ? t / wall : 0.0);
      status_writer.Write(s);
      if (robot.collisions() != reported_collisions) {
        spdlog::warn("navsim: collision at ({:.2f}, {:.2f}) t={:.2f}s (total {})", robot.true_pose().x,
                     robot.true_pose().y, t, robot.collisions());
        reported_collisions = robot.collisions();
      }
    }
    // Pace to `rate` times real time; sleeping only when ahead keeps long runs on schedule.
    const double ahead = steps * dt / rate - wall;
    if (ahead > 0) std::this_thread::sleep_for(std::chrono::duration<double>(ahead));
  }
  spdlog::info("navsim: stopped at t={:.2f}s, travelled {:.2f} m, {} collisions", simulation.now(),
               simulation.robot().distance_travelled(), simulation.robot().collisions());
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
