// navd and its robot on different machines, as deployed: network namespaces joined by a bridge
// (tests/support/virtual_lan.h), multicast off, only their own addresses used. navsim runs on one
// host, navd on another, and a client on a third sends the robot to a goal over TLS with a token.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "tests/support/keystore.h"
#include "tests/support/navd_fixture.h"
#include "tests/support/process.h"
#include "tests/support/virtual_lan.h"

namespace navd::testing {
namespace {

constexpr int kSimHost = 0, kNavdHost = 1, kClientHost = 2;

class TwoHosts : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const std::string why = VirtualLan::Unavailable(); !why.empty()) GTEST_SKIP() << why;
    lan_.emplace(3);
    keys_.emplace(std::vector<std::string>{VirtualLan::Address(kNavdHost)});
    dir_ = MakeTempDir();
  }

  // navd on its host with TLS and roles, and `dds_args`; returns once it listens.
  void StartNavd(const std::vector<std::string>& dds_args) {
    std::vector<std::string> argv{NavdBinary(),    "--use-sim-time",
                                  "--listen",      Server(),
                                  "--port-file",   dir_ + "/navd.port",
                                  "--tls-cert",    keys_->tls("navd.pem"),
                                  "--tls-key",     keys_->tls("navd.key"),
                                  "--auth-tokens", keys_->tokens(),
                                  "--dds-network", "all"};
    argv.insert(argv.end(), dds_args.begin(), dds_args.end());
    navd_.emplace(lan_->On(kNavdHost, argv), dir_ + "/navd.log");
    WaitForPortFile(dir_ + "/navd.port", *navd_, 20.0);
  }

  void StartNavsim(const std::vector<std::string>& dds_args) {
    std::vector<std::string> argv{NavsimBinary(), "--rate", "5", "--lockstep", "--dds-network", "all"};
    argv.insert(argv.end(), dds_args.begin(), dds_args.end());
    sim_.emplace(lan_->On(kSimHost, argv), dir_ + "/navsim.log");
  }

  static std::string Server() { return VirtualLan::Address(kNavdHost) + ":50051"; }

  // navctl on the client host, over TLS with the operator's token.
  CommandResult Navctl(const std::vector<std::string>& command, double timeout) {
    std::vector<std::string> argv{
        NavctlBinary(), "--server", Server(), "--tls-ca", keys_->tls("ca.pem"), "--token", keys_->token("operator")};
    argv.insert(argv.end(), command.begin(), command.end());
    return RunCommand(lan_->On(kClientHost, argv), timeout);
  }

  // The client sends the robot to a goal once navd has a pose from the robot's odometry.
  void ExpectGoalReached() {
    CommandResult pose;
    for (int i = 0; i < 60; ++i) {
      pose = Navctl({"pose"}, 10.0);
      if (pose.exit_code == 0) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
    }
    ASSERT_EQ(pose.exit_code, 0) << pose.output << Logs();
    const CommandResult r = Navctl({"navigate", "--to", "2.5,3", "--timeout", "120"}, 180.0);
    EXPECT_EQ(r.exit_code, 0) << r.output << Logs();
    EXPECT_NE(r.output.find("succeeded: goal reached"), std::string::npos) << r.output;
  }

  std::string Logs() {
    std::string s = "\n--- navd (" + navd_->Status() + ") ---\n" + navd_->Log();
    if (sim_) s += "--- navsim (" + sim_->Status() + ") ---\n" + sim_->Log();
    return s;
  }

  std::optional<VirtualLan> lan_;
  std::optional<Keystore> keys_;
  std::string dir_;
  std::optional<Process> sim_, navd_;
};

TEST_F(TwoHosts, SecuredNavdDrivesNavsimOnAnotherHostForAClientOnAThird) {
  StartNavsim({"--dds-peer", VirtualLan::Address(kNavdHost), "--dds-security", keys_->enclave("navsim")});
  StartNavd({"--dds-peer", VirtualLan::Address(kSimHost), "--dds-security", keys_->enclave("navd")});
  ExpectGoalReached();
  // A client on the third host without credentials gets nowhere.
  const CommandResult plain = RunCommand(
      lan_->On(kClientHost, {NavctlBinary(), "--server", Server(), "--tls-ca", keys_->tls("ca.pem"), "status"}), 20.0);
  EXPECT_NE(plain.exit_code, 0);
  EXPECT_NE(plain.output.find("GetStatus needs credentials"), std::string::npos) << plain.output;
}

TEST_F(TwoHosts, ADiscoveryServerIntroducesNavdAndNavsimWithoutMulticast) {
  const std::string server = VirtualLan::Address(kSimHost) + ":11811";
  Process discovery(lan_->On(kSimHost, {"/usr/bin/fast-discovery-server", "-i", "0", "-l",
                                        VirtualLan::Address(kSimHost), "-p", "11811"}),
                    dir_ + "/discovery.log");
  StartNavsim({"--dds-discovery-server", server});
  StartNavd({"--dds-discovery-server", server});
  ExpectGoalReached();
  EXPECT_TRUE(discovery.running()) << discovery.Log();
}

}  // namespace
}  // namespace navd::testing
