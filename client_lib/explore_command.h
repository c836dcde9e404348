#pragma once
// navctl explore: starts, stops or reports navd's exploration (MappingService); with --wait it
// follows the exploration to its end, printing progress, and with --measure it judges the result
// against the simulator: collisions and distance from navsim's ground truth (DDS), and the share
// of the world's reachable free space the served map shows.
#include <string>

#include "client_lib/navd_client.h"

namespace navd::navctl {

struct ExploreOptions {
  std::string action = "status";    // start, stop or status
  std::string method = "frontier";  // frontier, greedy or vfm
  double resolution = 0.0;          // m per cell; 0: navd's default
  double size = 0.0;                // m; 0: navd's default
  double max_time = 0.0;            // s of navd's clock; 0: no limit
  std::string planner;
  bool wait = false;     // start: follow to the end; exit 0 only when complete
  bool measure = false;  // with wait: judge against navsim and the world
  std::string world;     // with measure: the world navsim runs (default: the embedded one)
  int domain = 0;
  std::string dds_security;  // DDS Security enclave, with measure (navctl --dds-security)
  std::string robot_namespace;
  bool json = false;
};

// Returns the process exit code. Throws on bad options or RPC errors.
int RunExplore(Client& client, const ExploreOptions& options);

}  // namespace navd::navctl
