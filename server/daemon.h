#pragma once
// navd's wiring and life cycle: map, planning engine, localiser, navigation executive, DDS
// bridge, control loop and gRPC server, started in that order and stopped in reverse, with the
// robot commanded to stop before anything else goes down.
#include <atomic>

#include "server/daemon_options.h"

namespace navd::server {

// Runs until `stop` turns true. Returns the process exit code. Throws navd::Error for bad
// configuration (unreadable world or map, listen address in use).
int RunDaemon(const DaemonOptions& options, const std::atomic<bool>& stop);

}  // namespace navd::server
