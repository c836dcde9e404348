// navsim as a process: two robots and people in the warehouse, driven over loopback DDS by a
// scripted driver (this test), each robot on its own namespace; ground truth, the world's bodies,
// collisions and the CARMEN recording are checked against what the driver did.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <mutex>
#include <thread>

#include "dds/conversions.h"
#include "dds/participant.h"
#include "dds/point_cloud2.h"
#include "dds/topics.h"
#include "geometry_msgsPubSubTypes.h"
#include "nav_msgsPubSubTypes.h"
#include "navsim_msgsPubSubTypes.h"
#include "rosgraph_msgsPubSubTypes.h"
#include "sensor_msgsPubSubTypes.h"
#include "services/common/camera_frame.h"
#include "services/common/carmen_log.h"
#include "services/common/world.h"
#include "tests/support/navd_fixture.h"
#include "tests/support/process.h"

namespace navd::testing {
namespace {

using Odometry = nav_msgs::msg::dds_::Odometry_PubSubType;
using Twist = geometry_msgs::msg::dds_::Twist_PubSubType;

double Yaw(const nav_msgs::msg::dds_::Odometry_& m) {
  const auto& q = m.pose().pose().orientation();
  return std::atan2(2 * (q.w() * q.z() + q.x() * q.y()), 1 - 2 * (q.y() * q.y() + q.z() * q.z()));
}

TEST(NavsimScenario, TwoRobotsAndPeopleOverDdsWithNamespacesTruthAndCollisions) {
  const int domain = ReserveDomain();
  const std::string dir = MakeTempDir();
  const std::string record = dir + "/alpha.log";
  Process navsim({NavsimBinary(), "--scenario", SourceDir() + "/worlds/scenarios/warehouse_fleet.yaml", "--rate", "5",
                  "--domain", std::to_string(domain), "--record", record, "--record-robot", "alpha"},
                 dir + "/navsim.log");

  dds::Participant p({domain, dds::Network::kLoopback, "driver", {}, {}, {}});
  using dds::Reliability;
  dds::Writer<Twist> alpha_cmd(p, dds::TopicName("alpha", dds::kCmdVel), Reliability::kReliable);
  dds::Writer<Twist> beta_cmd(p, dds::TopicName("beta", dds::kCmdVel), Reliability::kReliable);
  dds::Reader<Odometry> alpha_truth(p, dds::TopicName("alpha", dds::kGroundTruth), Reliability::kBestEffort);
  dds::Reader<Odometry> beta_truth(p, dds::TopicName("beta", dds::kGroundTruth), Reliability::kBestEffort);
  dds::Reader<sensor_msgs::msg::dds_::LaserScan_PubSubType> alpha_scan(p, dds::TopicName("alpha", dds::kScan),
                                                                       Reliability::kBestEffort);
  dds::Reader<sensor_msgs::msg::dds_::LaserScan_PubSubType> bare_scan(p, dds::TopicName("", dds::kScan),
                                                                      Reliability::kBestEffort);
  dds::Reader<sensor_msgs::msg::dds_::JointState_PubSubType> alpha_joints(p, dds::TopicName("alpha", dds::kJointStates),
                                                                          Reliability::kBestEffort);
  dds::Reader<navsim_msgs::msg::dds_::SimStatus_PubSubType> alpha_status(p, dds::TopicName("alpha", dds::kSimStatus),
                                                                         Reliability::kReliable);
  dds::Reader<navsim_msgs::msg::dds_::SimStatus_PubSubType> beta_status(p, dds::TopicName("beta", dds::kSimStatus),
                                                                        Reliability::kReliable);
  dds::Reader<navsim_msgs::msg::dds_::WorldState_PubSubType> world(p, dds::kWorldState, Reliability::kBestEffort);
  std::mutex events_mutex;
  std::vector<navsim_msgs::msg::dds_::CollisionEvent_> events;
  dds::Reader<navsim_msgs::msg::dds_::CollisionEvent_PubSubType> collisions(
      p, dds::kCollisions, Reliability::kReliable, [&](const navsim_msgs::msg::dds_::CollisionEvent_& e) {
        std::lock_guard<std::mutex> lock(events_mutex);
        events.push_back(e);
      });

  // Wait for the simulator's truth of both robots.
  for (int i = 0; i < 200 && (!alpha_truth.Latest() || !beta_truth.Latest() || !world.Latest()); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(alpha_truth.Latest() && beta_truth.Latest() && world.Latest()) << navsim.Log();
  const auto alpha0 = *alpha_truth.Latest();
  const auto beta0 = *beta_truth.Latest();
  EXPECT_NEAR(alpha0.pose().pose().position().y(), 1.0, 0.01);
  EXPECT_NEAR(beta0.pose().pose().position().x(), 8.5, 0.01);

  // alpha drives up the corridor; beta drives forward (towards -x) into the shelving 1.3 m ahead.
  geometry_msgs::msg::dds_::Twist_ forward;
  forward.linear().x(0.3);
  geometry_msgs::msg::dds_::Twist_ ram;
  ram.linear().x(0.4);
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < until) {
    alpha_cmd.Write(forward);
    beta_cmd.Write(ram);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const auto s = beta_status.Latest();
    const auto a = alpha_truth.Latest();
    if (s && s->collisions() >= 1 && a && a->pose().pose().position().y() > 2.5) break;
  }
  const auto alpha1 = *alpha_truth.Latest();
  const auto beta1 = *beta_truth.Latest();
  // Each robot moved as commanded on its own namespace, and only it.
  EXPECT_GT(alpha1.pose().pose().position().y(), 2.5);
  EXPECT_NEAR(alpha1.pose().pose().position().x(), 0.8, 0.1);
  EXPECT_NEAR(Yaw(alpha1), M_PI / 2, 0.1);
  EXPECT_NEAR(beta1.pose().pose().position().x(), 7.0 + 0.2, 0.05);  // stopped at the shelf's face
  EXPECT_NEAR(beta1.pose().pose().position().y(), 8.5, 0.1);
  ASSERT_TRUE(beta_status.Latest());
  EXPECT_EQ(beta_status.Latest()->collisions(), 1u);
  ASSERT_TRUE(alpha_status.Latest());
  EXPECT_EQ(alpha_status.Latest()->collisions(), 0u);
  {
    std::lock_guard<std::mutex> lock(events_mutex);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].robot(), "beta");
    EXPECT_EQ(events[0].other(), "wall");
    EXPECT_NEAR(events[0].x(), 7.0, 0.05);
  }
  // The world's truth lists both robots and the people; scans and encoders flow per robot.
  const auto w = *world.Latest();
  int robots = 0, people = 0;
  for (const auto& b : w.bodies()) {
    robots += b.kind() == "robot";
    people += b.kind() == "person";
  }
  EXPECT_EQ(robots, 2);
  EXPECT_GE(people, 3);  // three at the start, at most one newcomer (max 4)
  EXPECT_LE(people, 4);
  ASSERT_TRUE(alpha_scan.Latest());
  EXPECT_EQ(alpha_scan.Latest()->ranges().size(), 683u);
  ASSERT_TRUE(alpha_joints.Latest());
  ASSERT_EQ(alpha_joints.Latest()->name().size(), 2u);
  EXPECT_EQ(alpha_joints.Latest()->name()[0], "left_wheel");
  EXPECT_GT(alpha_joints.Latest()->position()[0], 10.0);  // 1.5 m on a 5 cm wheel is ~5 turns
  EXPECT_EQ(bare_scan.count(), 0u);                       // nothing leaks outside the namespaces

  // Stopping navsim closes the recording: a CARMEN log of alpha's run.
  EXPECT_EQ(navsim.Stop(SIGINT, 10.0), 0) << navsim.Log();
  const CarmenLog log = ReadCarmenLog(record, /*strict=*/true);
  EXPECT_GT(log.scans.size(), 10u);
  ASSERT_FALSE(log.truth.empty());
  EXPECT_GT(log.truth.back().pose.y, 2.5);
  EXPECT_EQ(log.scans.front().ranges.size(), 683u);
}

TEST(NavsimScenario, BareMapServerMapRunsTheDefaultRobotAndBadStartsAreRefused) {
  const int domain = ReserveDomain();
  const std::string dir = MakeTempDir();
  // A 4 x 3 m room at 5 cm with a wall all round: the robot starts at its centre.
  std::string pixels;
  for (int row = 0; row < 60; ++row) {
    for (int col = 0; col < 80; ++col) pixels += (row == 0 || col == 0 || row == 59 || col == 79) ? '\x00' : '\xff';
  }
  std::ofstream(dir + "/room.pgm", std::ios::binary) << "P5 80 60 255\n" << pixels;
  std::ofstream(dir + "/room.yaml") << "image: room.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\n";
  Process navsim({NavsimBinary(), "--world", dir + "/room.yaml", "--domain", std::to_string(domain)},
                 dir + "/navsim.log");
  dds::Participant p({domain, dds::Network::kLoopback, "driver", {}, {}, {}});
  dds::Reader<Odometry> truth(p, dds::TopicName("", dds::kGroundTruth), dds::Reliability::kBestEffort);
  dds::Reader<sensor_msgs::msg::dds_::LaserScan_PubSubType> scan(p, dds::TopicName("", dds::kScan),
                                                                 dds::Reliability::kBestEffort);
  for (int i = 0; i < 200 && (!truth.Latest() || !scan.Latest()); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(truth.Latest() && scan.Latest()) << navsim.Log();
  EXPECT_NEAR(truth.Latest()->pose().pose().position().x(), 2.0, 0.05);
  EXPECT_NEAR(truth.Latest()->pose().pose().position().y(), 1.5, 0.05);
  // The URG sees the walls of the room: straight ahead (+x) the inner face of the wall at x = 3.95.
  const auto s = *scan.Latest();
  ASSERT_EQ(s.ranges().size(), 683u);
  EXPECT_NEAR(s.ranges()[341], 1.95, 0.1);

  const auto bad =
      RunCommand({NavsimBinary(), "--world", dir + "/room.yaml", "--start", "0.02,1.5", "--duration", "1"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("--start '0.02,1.5' puts the robot off the map or inside a wall"), std::string::npos)
      << bad.output;
}

TEST(NavsimScenario, NavctlClosesAndOpensADoorTheLaserSeesIt) {
  const int domain = ReserveDomain();
  const std::string dir = MakeTempDir();
  Process navsim({NavsimBinary(), "--scenario", SourceDir() + "/worlds/scenarios/office.yaml", "--rate", "5",
                  "--domain", std::to_string(domain), "--command-timeout", "1000"},
                 dir + "/navsim.log");
  dds::Participant p({domain, dds::Network::kLoopback, "driver", {}, {}, {}});
  std::mutex scans_mutex;
  std::vector<float> last_ranges;
  int scans = 0;
  dds::Reader<sensor_msgs::msg::dds_::LaserScan_PubSubType> scan(p, dds::TopicName("", dds::kScan),
                                                                 dds::Reliability::kBestEffort,
                                                                 [&](const sensor_msgs::msg::dds_::LaserScan_& m) {
                                                                   std::lock_guard<std::mutex> lock(scans_mutex);
                                                                   last_ranges = m.ranges();
                                                                   ++scans;
                                                                 });
  dds::Reader<navsim_msgs::msg::dds_::WorldState_PubSubType> world(p, dds::kWorldState, dds::Reliability::kBestEffort);
  // The beam from the start (1, 6, 0) through the middle of door s1 (2.5, 4.95) of the office.
  const double angle = std::atan2(4.95 - 6.0, 2.5 - 1.0);
  const size_t beam = static_cast<size_t>(std::lround((angle + 2 * M_PI / 3) / (4 * M_PI / 3 / 682)));
  auto range_after_next_scans = [&] {
    int seen;
    {
      std::lock_guard<std::mutex> lock(scans_mutex);
      seen = scans;
    }
    for (int i = 0; i < 200; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      std::lock_guard<std::mutex> lock(scans_mutex);
      if (scans >= seen + 2) return static_cast<double>(last_ranges.at(beam));
    }
    return -1.0;
  };
  for (int i = 0; i < 200 && !world.Latest(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(world.Latest()) << navsim.Log();
  ASSERT_EQ(world.Latest()->doors().size(), 8u);
  EXPECT_EQ(world.Latest()->doors()[0].name(), "s1");
  EXPECT_FALSE(world.Latest()->doors()[0].closed());
  EXPECT_GT(range_after_next_scans(), 2.0);  // through the open doorway into the room

  const auto closed = RunCommand({NavctlBinary(), "door", "s1", "close", "--domain", std::to_string(domain)});
  EXPECT_EQ(closed.exit_code, 0) << closed.output;
  EXPECT_NE(closed.output.find("door 's1' closed"), std::string::npos) << closed.output;
  EXPECT_NEAR(range_after_next_scans(), 1.0 / std::sin(-angle), 0.05);  // the door's face at y = 5.0

  const auto opened = RunCommand({NavctlBinary(), "door", "s1", "open", "--domain", std::to_string(domain)});
  EXPECT_EQ(opened.exit_code, 0) << opened.output;
  EXPECT_GT(range_after_next_scans(), 2.0);

  const auto unknown = RunCommand({NavctlBinary(), "door", "back", "close", "--domain", std::to_string(domain)});
  EXPECT_NE(unknown.exit_code, 0);
  EXPECT_NE(unknown.output.find("no door 'back' (doors: s1, s2, s3, s4, n1, n2, n3, n4)"), std::string::npos)
      << unknown.output;
}

// navsim --lockstep with a real navd: simulated time waits for a navd that is frozen (SIGSTOP),
// moves on without it after the timeout, and waits again once it answers.
TEST(NavsimLockstep, SimulatedTimeWaitsForNavdThenMovesOnWithoutAFrozenOne) {
  StackOptions options;
  options.rate = 20.0;
  options.sim_args = {"--lockstep-timeout", "1.5"};
  NavdStack stack(options);
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  dds::Participant p({stack.domain(), dds::Network::kLoopback, "clock-watcher", {}, {}, {}});
  dds::Reader<rosgraph_msgs::msg::dds_::Clock_PubSubType> clock(p, dds::kClock, dds::Reliability::kBestEffort);
  auto sim_time_after = [&](double wall) {
    std::this_thread::sleep_for(std::chrono::duration<double>(wall));
    const auto c = clock.Latest();
    return c ? dds::FromTime(c->clock()) : -1.0;
  };
  // The reader finds navsim's writer within a few seconds on a loaded machine.
  for (int i = 0; i < 200 && !clock.Latest(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const double running = sim_time_after(0.5);
  ASSERT_GT(running, 0.0) << stack.Logs();
  EXPECT_GT(sim_time_after(0.5) - running, 1.0) << "navsim is not running";

  // Frozen for less than the timeout: simulated time stands at navd's next tick.
  ASSERT_EQ(kill(stack.navd().pid(), SIGSTOP), 0);
  const double frozen = sim_time_after(0.2);
  const double held = sim_time_after(1.0);
  EXPECT_LT(held - frozen, 0.1) << "simulated time ran on while navd was frozen";
  // Past the timeout navsim steps on without it.
  const double released = sim_time_after(2.0);
  EXPECT_GT(released - held, 2.0) << "navsim kept waiting for a frozen navd";
  ASSERT_EQ(kill(stack.navd().pid(), SIGCONT), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_NE(stack.Logs().find("sent no next tick for 1.5 s"), std::string::npos) << stack.Logs();
  // Answering again, navd holds it again: frozen once more, time stands.
  ASSERT_EQ(kill(stack.navd().pid(), SIGSTOP), 0);
  const double again = sim_time_after(0.2);
  EXPECT_LT(sim_time_after(1.0) - again, 0.1);
  ASSERT_EQ(kill(stack.navd().pid(), SIGCONT), 0);
}

TEST(NavsimScenario, BadScenarioExitsNonZeroWithOneLine) {
  const std::string dir = MakeTempDir();
  const std::string path = dir + "/bad.yaml";
  std::ofstream(path) << "world: default\nrobots:\n  - {start: [0.05, 1.0, 0.0]}\n";
  const auto r = RunCommand({NavsimBinary(), "--scenario", path, "--duration", "1"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("bad.yaml:3: field 'robots[0].start' puts the robot inside or against a wall"),
            std::string::npos)
      << r.output;
}

// navsim's depth camera as a ROS 2 node sees it: sensor_msgs/PointCloud2 under its ROS type name
// on rt/camera/points, read with the generic field rules (fields found by name, point_step,
// row_step, byte order), in the camera's optical frame: put back on the robot by the office_3d
// world's mount, the floor lies at z = 0 and the corridor's table top at its 0.75 m.
TEST(NavsimScenario, DepthCameraCloudReadsAsRos2PointCloud2) {
  const int domain = ReserveDomain();
  const std::string dir = MakeTempDir();
  Process navsim({NavsimBinary(), "--scenario", SourceDir() + "/worlds/scenarios/office_3d.yaml", "--rate", "2",
                  "--domain", std::to_string(domain), "--view", "off"},
                 dir + "/navsim.log");
  EXPECT_STREQ(sensor_msgs::msg::dds_::PointCloud2_PubSubType().getName(), "sensor_msgs::msg::dds_::PointCloud2_");
  dds::Participant p({domain, dds::Network::kLoopback, "viewer", {}, {}, {}});
  dds::Reader<sensor_msgs::msg::dds_::PointCloud2_PubSubType> cloud(p, dds::TopicName("", dds::kCameraPoints),
                                                                    dds::Reliability::kBestEffort);
  for (int i = 0; i < 200 && !cloud.Latest(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(cloud.Latest()) << navsim.Log();
  const auto m = *cloud.Latest();
  EXPECT_EQ(m.header().frame_id(), "camera_depth_optical_frame");
  EXPECT_EQ(m.height(), 1u);
  EXPECT_GT(m.width(), 10000u);
  EXPECT_EQ(m.row_step(), m.width() * m.point_step());
  const std::vector<Eigen::Vector3f> points = dds::DecodeXyzCloud(m);
  EXPECT_EQ(points.size(), m.width());
  // The robot starts at (1.0, 6.0) facing +x; the table's top spans x 4.0-4.9, y 5.05-5.75.
  const World world = LoadWorldFile(SourceDir() + "/worlds/office_3d.yaml");
  ASSERT_TRUE(world.camera);
  const Eigen::Isometry3f to_robot = RobotFromOptical(*world.camera);
  int floor = 0, top = 0;
  for (const Eigen::Vector3f& q : points) {
    const Eigen::Vector3f r = to_robot * q;
    const Point2 at = world.start * Point2(r.x(), r.y());
    if (std::abs(r.z()) < 0.05) ++floor;
    if (at.x() > 3.95 && at.x() < 4.95 && at.y() > 5.0 && at.y() < 5.8 && std::abs(r.z() - 0.73) < 0.05) ++top;
  }
  EXPECT_GT(floor, static_cast<int>(points.size()) / 3);
  EXPECT_GT(top, 20);
}

}  // namespace
}  // namespace navd::testing
