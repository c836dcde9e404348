// navd's DDS policy: participants in loopback mode discover each other and exchange ROS 2-layout
// samples, and the kernel shows every socket of a running navd and navsim bound to 127.0.0.1 and
// no shared memory mapped (no shared-memory transport, no data sharing).
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "dds/participant.h"
#include "dds/topics.h"
#include "geometry_msgsPubSubTypes.h"
#include "tests/support/navd_fixture.h"
#include "tests/support/process.h"

namespace navd::testing {
namespace {

TEST(DdsLoopback, LoopbackParticipantsDiscoverEachOtherAndExchangeSamples) {
  const int domain = ReserveDomain();
  dds::Participant a({domain, dds::Network::kLoopback, "a", {}, {}, {}});
  dds::Participant b({domain, dds::Network::kLoopback, "b", {}, {}, {}});
  dds::Writer<geometry_msgs::msg::dds_::Twist_PubSubType> writer(a, "rt/cmd_vel", dds::Reliability::kReliable);
  dds::Reader<geometry_msgs::msg::dds_::Twist_PubSubType> reader(b, "rt/cmd_vel", dds::Reliability::kReliable);
  for (int i = 0; i < 100 && writer.matched() == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_EQ(writer.matched(), 1);
  geometry_msgs::msg::dds_::Twist_ m;
  m.linear().x(0.25);
  m.angular().z(-0.5);
  for (int i = 0; i < 100 && reader.count() == 0; ++i) {
    writer.Write(m);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(reader.Latest());
  EXPECT_DOUBLE_EQ(reader.Latest()->linear().x(), 0.25);
  EXPECT_DOUBLE_EQ(reader.Latest()->angular().z(), -0.5);
}

// Local addresses (hex, as in /proc/net/*) of the sockets process `pid` holds, from the kernel's
// tables: what it can send from, whatever its configuration says.
std::vector<std::string> SocketAddresses(pid_t pid, const std::string& table) {
  std::set<std::string> inodes;
  for (const auto& fd : std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/fd")) {
    std::error_code ec;
    const std::string target = std::filesystem::read_symlink(fd.path(), ec).string();
    if (target.rfind("socket:[", 0) == 0) inodes.insert(target.substr(8, target.size() - 9));
  }
  std::vector<std::string> out;
  std::ifstream in("/proc/" + std::to_string(pid) + "/net/" + table);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::istringstream f(line);
    std::string slot, local, remote, state, queues, timer, retr, uid, timeout, inode;
    f >> slot >> local >> remote >> state >> queues >> timer >> retr >> uid >> timeout >> inode;
    if (inodes.count(inode)) out.push_back(local.substr(0, local.find(':')));
  }
  return out;
}

// The files under /dev/shm process `pid` has mapped: Fast DDS's shared-memory transport and its
// data sharing both live there.
std::vector<std::string> SharedMemoryMappings(pid_t pid) {
  std::vector<std::string> out;
  std::ifstream in("/proc/" + std::to_string(pid) + "/maps");
  std::string line;
  while (std::getline(in, line)) {
    if (const auto at = line.find("/dev/shm/"); at != std::string::npos) out.push_back(line.substr(at));
  }
  return out;
}

TEST(DdsLoopback, NavdAndNavsimSocketsAreBoundToLoopbackOnly) {
  NavdStack stack;
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  for (Process* p : {&stack.navd(), stack.sim()}) {
    const auto udp = SocketAddresses(p->pid(), "udp");
    EXPECT_GE(udp.size(), 2u) << "DDS sockets expected";
    for (const auto& a : udp) EXPECT_EQ(a, "0100007F") << "UDP socket not on 127.0.0.1";
    EXPECT_TRUE(SocketAddresses(p->pid(), "udp6").empty()) << "no IPv6 DDS sockets";
    for (const auto& a : SocketAddresses(p->pid(), "tcp")) EXPECT_EQ(a, "0100007F");
    // gRPC listens on an IPv4-mapped IPv6 socket: ::ffff:127.0.0.1.
    for (const auto& a : SocketAddresses(p->pid(), "tcp6")) EXPECT_EQ(a, "0000000000000000FFFF00000100007F");
    // Fast DDS 2.9's data sharing segfaulted navd in its shared history: it stays off.
    for (const auto& m : SharedMemoryMappings(p->pid())) ADD_FAILURE() << "maps shared memory " << m;
  }
}

TEST(DdsLoopback, TypeNamesFollowRos2Conventions) {
  geometry_msgs::msg::dds_::Twist_PubSubType twist;
  EXPECT_STREQ(twist.getName(), "geometry_msgs::msg::dds_::Twist_");
  EXPECT_EQ(dds::TopicName("", dds::kScan), "rt/scan");
  EXPECT_EQ(dds::TopicName("robot1", dds::kScan), "rt/robot1/scan");
}

}  // namespace
}  // namespace navd::testing
