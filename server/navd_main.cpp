// navd: the navigation daemon. Parses the command line and runs the daemon until SIGINT/SIGTERM.
#include <spdlog/cfg/env.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "dds/participant_flags.h"
#include "server/daemon.h"

namespace {
navd::server::DaemonSignals g_signals;
void OnStop(int) { g_signals.stop = true; }
void OnHangUp(int) { g_signals.reload_tokens = true; }

// The command line as parsed, before the values that need converting reach DaemonOptions.
struct CommandLine {
  navd::server::DaemonOptions o;
  std::string network = "loopback";
  std::vector<double> sonar_degrees;  // degrees
  std::vector<double> initial;        // X Y THETA
  CLI::Option* view = nullptr;
};

// What navd serves and where: the world or map, the gRPC address, the live view.
void AddServingOptions(CLI::App& app, CommandLine& c) {
  auto* world =
      app.add_option("--world", c.o.world_path, "World YAML (map and robot); default: the embedded warehouse");
  app.add_option("--map", c.o.map_path, "Map file: ROS map_server YAML (+PGM) or a world YAML")->excludes(world);
  app.add_option("--listen", c.o.listen, "gRPC listen address HOST:PORT (port 0 picks a free one)");
  app.add_option("--port-file", c.o.port_file, "Write the bound gRPC port to this file");
  c.view = app.add_option("--view", c.o.view,
                          "Live view HOST:PORT: the Foxglove WebSocket server and the page at http://HOST:PORT/ "
                          "(port 0 picks a free one); off: none");
  app.add_option("--view-port-file", c.o.view_port_file, "Write the bound view port to this file");
}

// TLS, mutual TLS and the callers' roles on gRPC.
void AddSecurityOptions(CLI::App& app, CommandLine& c) {
  navd::server::security::GrpcSecurityOptions& sec = c.o.grpc_security;
  app.add_option("--tls-cert", sec.tls_cert, "Serve gRPC over TLS with this PEM certificate (chain); needs --tls-key");
  app.add_option("--tls-key", sec.tls_key, "The PEM private key of --tls-cert");
  app.add_option("--tls-client-ca", sec.tls_client_ca,
                 "Mutual TLS: accept only clients whose certificate this PEM CA signed");
  app.add_option("--auth-tokens", sec.auth_tokens,
                 "Roles per caller: a file of 'TOKEN ROLE' or 'cn:CERT_NAME ROLE' lines (viewer, operator, admin), "
                 "mode 600; reloaded on SIGHUP; needs TLS");
  app.add_flag("--insecure", sec.insecure,
               "Allow plain-text gRPC on a non-loopback --listen address (anyone who reaches it can drive the robot)");
}

// DDS: the participant, the topics' namespace and the clock they carry.
void AddTransportOptions(CLI::App& app, CommandLine& c) {
  navd::dds::AddParticipantFlags(app, c.o.dds, c.network);
  app.add_option("--namespace", c.o.robot_namespace, "Robot namespace for topics (rt/<ns>/scan ...)");
  app.add_flag("--use-sim-time", c.o.use_sim_time, "Follow the simulator's rt/clock instead of the system clock");
}

// The localiser and its particle filter.
void AddLocalisationOptions(CLI::App& app, CommandLine& c) {
  app.add_option("--localizer", c.o.localizer,
                 "amcl (particle filter on laser scans, default), ekf (seed 002's EKF with scan-to-map matching), "
                 "calibration (seed 000's odometric calibration), histogram (grid localisation, small maps), odometry, "
                 "or auto (the chapter-10 arbiter chooses)")
      ->check(CLI::IsMember({"amcl", "ekf", "calibration", "histogram", "odometry", "auto"}));
  app.add_option("--odometry", c.o.odometry,
                 "odom (the robot's rt/odom, default) or encoders (navd integrates rt/joint_states wheel angles "
                 "with the robot's kinematics, book ch. 1)")
      ->check(CLI::IsMember({"odom", "encoders"}));
  app.add_option("--laser-model", c.o.laser_model,
                 "The particle filter's sensor model: likelihood_field (default) or beam (ray casts per particle)")
      ->check(CLI::IsMember({"likelihood_field", "beam"}));
  app.add_option("--odom-alpha", c.o.odom_alpha,
                 "The particle filter's odometry noise, AMCL's odom_alpha1..4 (default 0.1, for navsim's robots; the "
                 "real logs: 0.01)")
      ->check(CLI::Range(1e-6, 10.0));
  app.add_option("--update-min-d", c.o.update_min_d,
                 "The particle filter weighs a scan after this many metres of motion, AMCL's update_min_d (default "
                 "0.05, for navsim's robots; a real scanner logging every few centimetres: 0.25)")
      ->check(CLI::Range(1e-6, 100.0));
  app.add_option("--update-min-a", c.o.update_min_a,
                 "... or this many radians of turn, AMCL's update_min_a (default 0.05; real scanners: 0.2)")
      ->check(CLI::Range(1e-6, 10.0));
}

// How the robot behaves: the utility brain, range sensors' reflexes, among people.
void AddBehaviourOptions(CLI::App& app, CommandLine& c) {
  app.add_option("--brain", c.o.brain_path, "Utility-function brain YAML (default: built in, as config/brain.yaml)");
  app.add_option("--rear-range-frame", c.o.rear_range_frame,
                 "frame_id of the rear-facing range sensor on rt/<ns>/ir, checked before backing up ('' for none)")
      ->capture_default_str();
  app.add_option("--sonar-reflexes", c.o.sonar_reflexes,
                 "Seed 004's reflexes on the sonar ring of rt/<ns>/sonar: steer off what only the sonar finds "
                 "(true or false)")
      ->capture_default_str();
  app.add_flag("--people-aware", c.o.people_aware,
               "Book chapter 7 among people: track the people the laser sees and drive each leg with the crowd RRT "
               "in a model-predictive loop, keeping out of their personal space");
  app.add_option("--crowd-speed", c.o.crowd_speed, "With --people-aware: the desired speed among people, m/s")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option(
         "--people-source", c.o.people_source,
         "With --people-aware, where people come from: laser (navd tracks the laser's blobs) or topic "
         "(a people detector's people_msgs/People on rt/<ns>/people, base_link frame; navsim's `people` sensor)")
      ->check(CLI::IsMember({"laser", "topic"}))
      ->capture_default_str();
  app.add_option("--sonar-angles", c.sonar_degrees,
                 "Mounting angle of each sonar_<i> in degrees, robot frame, counter-clockwise from ahead "
                 "(default: a Pioneer ring of 16)")
      ->delimiter(',')
      ->check(CLI::Range(-360.0, 360.0));
}

// The control loop, the costmap and the pose to start from.
void AddControlOptions(CLI::App& app, CommandLine& c) {
  app.add_option("--control-rate", c.o.control_rate, "Control loop rate, Hz")->check(CLI::Range(1.0, 200.0));
  app.add_option("--inflation-margin", c.o.inflation_margin, "Metres added to the robot radius for lethal inflation")
      ->check(CLI::Range(0.0, 5.0));
  app.add_option("--cost-decay", c.o.cost_decay, "Metres of decaying cost beyond the inflation (0: none)")
      ->check(CLI::Range(0.0, 10.0));
  app.add_option("--initial-pose", c.initial, "Initial pose X Y THETA in the map frame (default: the world's start)")
      ->expected(3);
}

// The parsed values DaemonOptions takes converted: radians, the initial pose, what was asked.
navd::server::DaemonOptions Finish(CommandLine c) {
  navd::server::DaemonOptions o = std::move(c.o);
  o.view_asked = c.view->count() > 0;
  for (double d : c.sonar_degrees) o.sonar_angles.push_back(d * M_PI / 180.0);
  if (c.initial.size() == 3) {
    o.initial_pose_set = true;
    std::copy(c.initial.begin(), c.initial.end(), o.initial_pose);
  }
  o.dds.name = "navd";
  return o;
}
}  // namespace

int main(int argc, char** argv) {
  CommandLine c;
  CLI::App app{"navd: navigation daemon (planning, localisation, mapping, navigation over gRPC; sensors over DDS)"};
  AddServingOptions(app, c);
  AddSecurityOptions(app, c);
  AddTransportOptions(app, c);
  AddLocalisationOptions(app, c);
  AddBehaviourOptions(app, c);
  AddControlOptions(app, c);
  try {
    app.parse(argc, argv);
    c.o.dds.network = navd::dds::ParseNetwork(c.network);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navd: %s\n", e.what());
    return 2;
  }
  // SPDLOG_LEVEL=debug (or e.g. "info"): the log's level, as spdlog reads it.
  spdlog::cfg::load_env_levels();
  const navd::server::DaemonOptions o = Finish(std::move(c));
  std::signal(SIGINT, OnStop);
  std::signal(SIGTERM, OnStop);
  std::signal(SIGHUP, OnHangUp);
  try {
    return navd::server::RunDaemon(o, g_signals);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navd: %s\n", e.what());
    return 2;
  }
}
