#include "client_lib/replay_link.h"

#include <chrono>
#include <stdexcept>
#include <thread>

#include "dds/conversions.h"
#include "dds/participant.h"
#include "dds/topics.h"
#include "geometry_msgsPubSubTypes.h"
#include "nav_msgsPubSubTypes.h"
#include "rosgraph_msgsPubSubTypes.h"
#include "sensor_msgsPubSubTypes.h"

namespace navd::navctl {

// Best effort and shallow for what the robot sends (a late reading is worth less than the next),
// reliable for the poses judged.
struct ReplayLink::Endpoints {
  Endpoints(const ReplayLinkOptions& o, ReplayLink* link)
      : participant(ParticipantOptionsOf(o)),
        clock(participant, dds::kClock, dds::Reliability::kBestEffort, 1),
        odom(participant, dds::TopicName(o.robot_namespace, dds::kOdom), dds::Reliability::kBestEffort, 5),
        scan(participant, dds::TopicName(o.robot_namespace, dds::kScan), dds::Reliability::kBestEffort, 5),
        pose(
            participant, dds::TopicName(o.robot_namespace, dds::kPose), dds::Reliability::kReliable,
            [link](const geometry_msgs::msg::dds_::PoseWithCovarianceStamped_& m) {
              std::lock_guard<std::mutex> lock(link->mutex_);
              link->poses_.push_back({dds::FromTime(m.header().stamp()), dds::FromPose(m.pose().pose())});
            },
            50) {}

  static dds::ParticipantOptions ParticipantOptionsOf(const ReplayLinkOptions& o) {
    dds::ParticipantOptions p;
    p.domain = o.domain;
    p.name = "navctl-replay";
    p.security_enclave = o.dds_security;
    return p;
  }

  dds::Participant participant;
  dds::Writer<rosgraph_msgs::msg::dds_::Clock_PubSubType> clock;
  dds::Writer<nav_msgs::msg::dds_::Odometry_PubSubType> odom;
  dds::Writer<sensor_msgs::msg::dds_::LaserScan_PubSubType> scan;
  dds::Reader<geometry_msgs::msg::dds_::PoseWithCovarianceStamped_PubSubType> pose;
  sensor_msgs::msg::dds_::LaserScan_ scan_message;  // reused: its ranges keep their storage
};

ReplayLink::ReplayLink(const ReplayLinkOptions& options)
    : options_(options), endpoints_(std::make_unique<Endpoints>(options, this)) {}

// Here, where Endpoints is whole. The endpoints (whose reader's callback fills poses_) are declared
// last and so go first.
ReplayLink::~ReplayLink() = default;

void ReplayLink::WaitForNavd(double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while ((endpoints_->scan.matched() == 0 || endpoints_->odom.matched() == 0) &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  if (endpoints_->scan.matched() == 0 || endpoints_->odom.matched() == 0)
    throw std::runtime_error("no navd reading " + dds::TopicName(options_.robot_namespace, dds::kScan) +
                             " on DDS domain " + std::to_string(options_.domain) + " within " +
                             std::to_string(seconds).substr(0, 4) + " s");
}

void ReplayLink::PublishOdometry(double stamp, const Pose2& odometry) {
  rosgraph_msgs::msg::dds_::Clock_ c;
  c.clock(dds::ToTime(stamp));
  endpoints_->clock.Write(c);
  endpoints_->odom.Write(dds::MakeOdometry(stamp, odometry, 0.0, 0.0, 0.0, Eigen::Matrix3d::Zero(), "odom"));
}

void ReplayLink::PublishScan(const CarmenScan& s, double range_max) {
  sensor_msgs::msg::dds_::LaserScan_& msg = endpoints_->scan_message;
  msg.header(dds::MakeHeader(s.timestamp, "base_scan"));
  msg.angle_min(static_cast<float>(s.angle_min));
  msg.angle_increment(static_cast<float>(s.angle_increment));
  msg.angle_max(static_cast<float>(s.angle_min + (s.ranges.size() - 1) * s.angle_increment));
  msg.range_min(0.05f);
  msg.range_max(static_cast<float>(range_max));
  msg.ranges(s.ranges);
  endpoints_->scan.Write(msg);
}

std::vector<StampedPose> ReplayLink::TakePoses() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<StampedPose> taken;
  taken.swap(poses_);
  return taken;
}

std::string ReplayLink::pose_topic() const { return dds::TopicName(options_.robot_namespace, dds::kPose); }

}  // namespace navd::navctl
