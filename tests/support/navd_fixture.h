#pragma once
// Starts a real navsim and a real navd on loopback with a reserved DDS domain and a free gRPC
// port (navd binds port 0 and reports it through --port-file), and a client for them.
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "client_lib/navd_client.h"
#include "client_lib/telemetry.h"
#include "tests/support/process.h"

namespace navd::testing {

struct StackOptions {
  double rate = 5.0;         // navsim --rate
  bool use_sim_time = true;  // navd --use-sim-time
  bool lockstep = true;      // navsim --lockstep: figures in simulated time do not depend on load
  bool start_sim = true;
  std::vector<std::string> navd_args;  // extra arguments
  std::vector<std::string> sim_args;
  ClientOptions client;  // the stack's client; its server is set to navd's address
};

class NavdStack {
 public:
  explicit NavdStack(const StackOptions& options = {});
  ~NavdStack();

  Client& client() { return *client_; }
  // A client of this stack's navd with other credentials (`o.server` is replaced).
  std::unique_ptr<Client> MakeClient(ClientOptions o) const;
  const std::string& address() const { return address_; }
  int domain() const { return domain_; }
  const std::string& dir() const { return dir_; }
  Process& navd() { return *navd_; }
  // A DDS subscriber to this stack's telemetry and simulator truth (the test's own participant).
  std::unique_ptr<Telemetry> MakeTelemetry() const;
  Process* sim() { return sim_.get(); }
  // Waits until navd reports a pose (odometry flowing). Returns false on timeout.
  bool WaitForPose(double timeout);
  std::string Logs() const;

 private:
  int domain_;
  std::string dir_;
  std::string address_;
  std::unique_ptr<Process> sim_;
  std::unique_ptr<Process> navd_;
  std::unique_ptr<Client> client_;
};

// Success when two simulator status samples `gap` simulated seconds apart show the true position
// moved less than a millimetre; the first is taken `settle` simulated seconds after the next
// sample (time for a robot told to stop to brake).
::testing::AssertionResult RobotStandsStill(const Telemetry& telemetry, double gap = 0.3, double settle = 0.0);

// Paths of the built binaries and the source tree (set by CMake).
std::string NavdBinary();
std::string NavsimBinary();
std::string NavctlBinary();
std::string NavdReplayBinary();
std::string NavdExploreBinary();
std::string SourceDir();

}  // namespace navd::testing
