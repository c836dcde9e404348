#pragma once
// navd's settings, filled from the command line (navd_main.cpp).
#include <string>
#include <vector>

#include "dds/participant.h"
#include "server/security/grpc_security.h"

namespace navd::server {

struct DaemonOptions {
  std::string world_path;  // world YAML; empty and map_path empty: the embedded warehouse
  std::string map_path;    // map_server YAML or world YAML (map only)
  std::string listen = "127.0.0.1:50051";
  std::string port_file;  // when set, the bound port is written here (atomically)
  // The live view's listener (view_feed.h), "off" for none. The default port may be taken (another
  // navd on this host): then navd runs without a view and says so; a port asked for must bind.
  std::string view = "127.0.0.1:8765";
  bool view_asked = false;     // --view was given
  std::string view_port_file;  // when set, the bound view port is written here (atomically)
  security::GrpcSecurityOptions grpc_security;
  dds::ParticipantOptions dds;
  std::string robot_namespace;
  bool use_sim_time = false;
  std::string localizer = "amcl";                // amcl | ekf | calibration | histogram | odometry | auto
  std::string odometry = "odom";                 // odom: the robot's rt/odom; encoders: navd integrates joint_states
  std::string laser_model = "likelihood_field";  // the particle filter's: likelihood_field | beam
  // The particle filter's odometry noise, AMCL's odom_alpha1..4 (variance per unit of motion
  // squared); 0: the filter's default, which suits navsim's robots. Better odometry wants less.
  double odom_alpha = 0.0;
  // The particle filter weighs a scan only after this much motion since the last it weighed
  // (AMCL's update_min_d in m, update_min_a in rad); 0: the filter's default (0.05, 0.05), for
  // navsim's robots. A real scanner logging every few centimetres wants AMCL's 0.25 and 0.2.
  double update_min_d = 0.0, update_min_a = 0.0;
  std::string brain_path;  // utility-function brain YAML; empty: the built-in default
  std::string rear_range_frame = "ir_2";
  bool sonar_reflexes = true;           // seed 004's reflexes on the sonar ring of rt/<ns>/sonar
  std::vector<double> sonar_angles;     // rad, mounting angle of sonar_<i>; empty: a Pioneer ring
  bool people_aware = false;            // book chapter 7: track people, steer legs with the crowd RRT
  double crowd_speed = 1.5;             // m/s, the crowd RRT's desired speed (capped by the robot's)
  std::string people_source = "laser";  // laser: navd's tracker; topic: a detector's rt/<ns>/people
  double control_rate = 20.0;           // Hz, in the daemon's clock
  double sensor_timeout = 0.3;          // s without odometry or laser before the robot is stopped (3 scans)
  double inflation_margin = 0.10;       // m added to the robot radius for planning
  double cost_decay = 0.50;             // m of decaying cost beyond the inflation (keeps paths off walls)
  bool initial_pose_set = false;        // --initial-pose given
  double initial_pose[3] = {0, 0, 0};
};

}  // namespace navd::server
