// DDS Security with the enclaves scripts/make-keystore makes: secured navd and navsim work
// together, and a participant without credentials neither reads the robot's scans nor drives it.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "dds/participant.h"
#include "dds/topics.h"
#include "geometry_msgsPubSubTypes.h"
#include "nav_msgsPubSubTypes.h"
#include "sensor_msgsPubSubTypes.h"
#include "tests/support/keystore.h"
#include "tests/support/navd_fixture.h"

namespace navd::testing {
namespace {

using dds::Reliability;
using Odometry = nav_msgs::msg::dds_::Odometry_PubSubType;
using Scan = sensor_msgs::msg::dds_::LaserScan_PubSubType;
using Twist = geometry_msgs::msg::dds_::Twist_PubSubType;

// One participant's view of the robot and its wheels.
struct Station {
  Station(int domain, const std::string& name, const std::string& enclave)
      : participant({domain, dds::Network::kLoopback, name, {}, enclave, {}}),
        scans(participant, dds::TopicName("", dds::kScan), Reliability::kBestEffort),
        truth(participant, dds::TopicName("", dds::kGroundTruth), Reliability::kBestEffort),
        cmd(participant, dds::TopicName("", dds::kCmdVel), Reliability::kReliable) {}

  // Publishes `speed` ahead at 20 Hz for `seconds` of wall time.
  void Drive(double speed, double seconds) {
    geometry_msgs::msg::dds_::Twist_ t;
    t.linear().x(speed);
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      cmd.Write(t);
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }

  dds::Participant participant;
  dds::Reader<Scan> scans;
  dds::Reader<Odometry> truth;
  dds::Writer<Twist> cmd;
};

double Distance(const nav_msgs::msg::dds_::Odometry_& a, const nav_msgs::msg::dds_::Odometry_& b) {
  return std::hypot(a.pose().pose().position().x() - b.pose().pose().position().x(),
                    a.pose().pose().position().y() - b.pose().pose().position().y());
}

TEST(DdsSecurity, AParticipantWithoutCredentialsNeitherReadsScansNorDrivesTheRobot) {
  const Keystore keys;
  const int domain = ReserveDomain();
  const std::string dir = MakeTempDir();
  Process navsim(
      {NavsimBinary(), "--domain", std::to_string(domain), "--rate", "5", "--dds-security", keys.enclave("navsim")},
      dir + "/navsim.log");
  Station operator_station(domain, "navctl", keys.enclave("navctl"));
  Station intruder(domain, "intruder", "");

  for (int i = 0; i < 300 && (!operator_station.truth.Latest() || operator_station.scans.count() == 0); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(operator_station.truth.Latest()) << "the secured participant gets no ground truth\n" << navsim.Log();
  ASSERT_GT(operator_station.scans.count(), 0u);

  const auto before = *operator_station.truth.Latest();
  intruder.Drive(0.4, 2.0);  // 10 simulated seconds: 4 m if navsim obeyed
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const auto after_intruder = *operator_station.truth.Latest();
  EXPECT_LT(Distance(before, after_intruder), 1e-3) << "navsim obeyed an unauthenticated cmd_vel";
  EXPECT_EQ(intruder.scans.count(), 0u) << "an unauthenticated participant read the scans";
  EXPECT_FALSE(intruder.truth.Latest()) << "an unauthenticated participant read the ground truth";
  EXPECT_GT(operator_station.scans.count(), 10u);

  // The same command from a participant the deployment's CA admitted moves the robot: the path
  // the intruder was refused works.
  operator_station.Drive(0.4, 1.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_GT(Distance(after_intruder, *operator_station.truth.Latest()), 0.3) << navsim.Log();
  EXPECT_TRUE(navsim.running()) << navsim.Log();
}

TEST(DdsSecurity, SecuredNavdAndNavsimNavigate) {
  const Keystore keys;
  StackOptions o;
  o.navd_args = {"--dds-security", keys.enclave("navd")};
  o.sim_args = {"--dds-security", keys.enclave("navsim")};
  NavdStack stack(o);
  ASSERT_TRUE(stack.WaitForPose(30.0)) << stack.Logs();
  const v1::NavigationResult r = stack.client().NavigateTo(2.5, 3.0, std::nullopt, {}, 120.0);
  EXPECT_EQ(r.outcome(), v1::SUCCEEDED) << r.ShortDebugString() << "\n" << stack.Logs();

  // navctl's DDS commands join with the keystore's navctl enclave, and only with it.
  const std::vector<std::string> truth{NavctlBinary(), "--dds-security", keys.enclave("navctl"),
                                       "truth",        "--domain",       std::to_string(stack.domain())};
  CommandResult t = RunCommand(truth, 30.0);
  EXPECT_EQ(t.exit_code, 0) << t.output;
  t = RunCommand({NavctlBinary(), "truth", "--domain", std::to_string(stack.domain()), "--wait", "2"}, 30.0);
  EXPECT_NE(t.exit_code, 0) << t.output;
  EXPECT_NE(t.output.find("no simulator status"), std::string::npos) << t.output;
}

TEST(DdsSecurity, AnIncompleteEnclaveIsRefusedInOneLine) {
  const std::string empty = MakeTempDir();
  for (const std::string& binary : {NavdBinary(), NavsimBinary()}) {
    const CommandResult r =
        RunCommand({binary, "--domain", std::to_string(ReserveDomain()), "--dds-security", empty}, 20.0);
    EXPECT_NE(r.exit_code, 0) << binary;
    EXPECT_NE(r.output.find("DDS security enclave " + empty + " lacks a readable identity_ca.cert.pem"),
              std::string::npos)
        << r.output;
  }
}

}  // namespace
}  // namespace navd::testing
