#pragma once
// navctl follow: runs a waypoint mission on navd and, with --measure, judges it against the
// simulator's ground truth over DDS (distance, simulated time, localisation error, collisions),
// the figures of seed 000's delivery runs.
#include <cstdint>
#include <string>

#include "client_lib/navd_client.h"

namespace navd::navctl {

struct FollowOptions {
  std::string waypoints;  // "X,Y[,THETA];X,Y;..."
  std::string scenario;   // or: the targets of this navsim scenario file
  bool cyclic = false;
  uint32_t laps = 0;
  double max_distance = 0.0;  // m
  double timeout = 0.0;       // s of wall time, 0 = none
  std::string planner;
  bool preempt = false;
  bool json = false;
  bool measure = false;      // compare with navsim's ground truth
  int domain = 0;            // DDS domain of navsim, with measure
  std::string dds_security;  // DDS Security enclave, with measure (navctl --dds-security)
  std::string robot_namespace;
};

// Returns the process exit code: 0 when the mission succeeded. Throws on bad options or RPC errors.
int RunFollow(Client& client, const FollowOptions& options);

}  // namespace navd::navctl
