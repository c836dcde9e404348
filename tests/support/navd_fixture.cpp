#include "tests/support/navd_fixture.h"

#include <signal.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "dds/conversions.h"

namespace navd::testing {

std::string NavdBinary() { return NAVD_BINARY; }
std::string NavsimBinary() { return NAVSIM_BINARY; }
std::string NavctlBinary() { return NAVCTL_BINARY; }
std::string NavdReplayBinary() { return NAVD_REPLAY_BINARY; }
std::string NavdExploreBinary() { return NAVD_EXPLORE_BINARY; }
std::string SourceDir() { return NAVD_SOURCE_DIR; }

::testing::AssertionResult RobotStandsStill(const Telemetry& telemetry, double gap, double settle) {
  // Simulated time, not the wall's: under navsim --lockstep the simulation waits for navd, and a
  // loaded machine stalls it for longer than any wall-clock pause a test could afford.
  const auto sample_after = [&](std::optional<double> since, double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (std::chrono::steady_clock::now() < end) {
      auto s = telemetry.WaitForSimStatus(5.0);
      if (!s) return s;
      if (!since) since = dds::FromTime(s->header().stamp());
      if (dds::FromTime(s->header().stamp()) >= *since + seconds) return s;
    }
    return std::optional<navsim_msgs::msg::dds_::SimStatus_>{};
  };
  const auto a = sample_after(std::nullopt, settle);
  if (!a) return ::testing::AssertionFailure() << "no simulator status over DDS";
  const double from = dds::FromTime(a->header().stamp());
  const auto b = sample_after(from, gap);
  if (!b)
    return ::testing::AssertionFailure() << "no simulator status over DDS " << gap << " s after t=" << from << " s";
  const double moved = std::hypot(a->x() - b->x(), a->y() - b->y());
  if (moved >= 1e-3)
    return ::testing::AssertionFailure() << "the robot moved " << moved << " m from t=" << from
                                         << " s to t=" << dds::FromTime(b->header().stamp()) << " s (simulated)";
  return ::testing::AssertionSuccess();
}

NavdStack::NavdStack(const StackOptions& o) : domain_(ReserveDomain()), dir_(MakeTempDir()) {
  const std::string domain = std::to_string(domain_);
  if (o.start_sim) {
    std::vector<std::string> args{NavsimBinary(), "--domain", domain, "--rate", std::to_string(o.rate)};
    if (o.lockstep) args.emplace_back("--lockstep");
    args.insert(args.end(), o.sim_args.begin(), o.sim_args.end());
    sim_ = std::make_unique<Process>(args, dir_ + "/navsim.log");
  }
  const std::string port_file = dir_ + "/navd.port";
  std::vector<std::string> args{NavdBinary(), "--domain", domain, "--listen", "127.0.0.1:0", "--port-file", port_file};
  if (o.use_sim_time) args.emplace_back("--use-sim-time");
  args.insert(args.end(), o.navd_args.begin(), o.navd_args.end());
  navd_ = std::make_unique<Process>(args, dir_ + "/navd.log");

  try {
    address_ = "127.0.0.1:" + WaitForPortFile(port_file, *navd_, 20.0);
  } catch (const std::runtime_error&) {
    throw std::runtime_error("navd did not start (" + navd_->Status() + "):\n" + Logs());
  }
  client_ = MakeClient(o.client);
  if (!client_->WaitForConnected(10.0)) throw std::runtime_error("cannot connect to navd at " + address_);
}

std::unique_ptr<Client> NavdStack::MakeClient(ClientOptions o) const {
  o.server = address_;
  return std::make_unique<Client>(o);
}

NavdStack::~NavdStack() {
  navd_->Stop(SIGTERM, 10.0);
  if (sim_) sim_->Stop(SIGTERM, 10.0);
}

std::unique_ptr<Telemetry> NavdStack::MakeTelemetry() const {
  TelemetryOptions o;
  o.dds.domain = domain_;
  o.dds.name = "navd-test";
  return std::make_unique<Telemetry>(o);
}

bool NavdStack::WaitForPose(double timeout) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
  while (std::chrono::steady_clock::now() < end) {
    try {
      client_->GetPose();
      return true;
    } catch (const ClientError&) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
  return false;
}

std::string NavdStack::Logs() const {
  std::string s = "--- navd log (" + navd_->Status() + ") ---\n" + navd_->Log();
  if (sim_) s += "--- navsim log (" + sim_->Status() + ") ---\n" + sim_->Log();
  return s;
}

}  // namespace navd::testing
