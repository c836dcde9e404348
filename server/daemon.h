#pragma once
// navd's wiring and life cycle: map, planning engine, localiser, navigation executive, DDS
// bridge, control loop and gRPC server, started in that order and stopped in reverse, with the
// robot commanded to stop before anything else goes down.
#include <atomic>

#include "server/daemon_options.h"

namespace navd::server {

// What navd's signal handlers ask of the running daemon.
struct DaemonSignals {
  std::atomic<bool> stop{false};           // SIGINT, SIGTERM: stop the robot, then shut down
  std::atomic<bool> reload_tokens{false};  // SIGHUP: re-read the --auth-tokens file
};

// Runs until `signals.stop` turns true. Returns the process exit code. Throws navd::Error for bad
// configuration (unreadable world or map, listen address in use, contradictory security options).
int RunDaemon(const DaemonOptions& options, DaemonSignals& signals);

}  // namespace navd::server
