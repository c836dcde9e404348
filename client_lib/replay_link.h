#pragma once
// navctl replay's side of DDS: what a robot sends navd (rt/clock in log time, rt/<ns>/odom,
// rt/<ns>/scan) and the poses navd publishes back (rt/<ns>/pose), on one participant.
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "services/common/carmen_log.h"
#include "services/common/pose2.h"

namespace navd::navctl {

// A pose navd published, stamped in log time (s).
struct StampedPose {
  double stamp;
  Pose2 pose;  // map frame
};

struct ReplayLinkOptions {
  int domain = 0;
  std::string dds_security;  // DDS Security enclave; empty: none
  std::string robot_namespace;
};

class ReplayLink {
 public:
  explicit ReplayLink(const ReplayLinkOptions& options);
  ~ReplayLink();
  ReplayLink(const ReplayLink&) = delete;
  ReplayLink& operator=(const ReplayLink&) = delete;

  // Waits up to `seconds` for navd's scan and odometry readers; throws std::runtime_error naming
  // the topic and domain when none appears.
  void WaitForNavd(double seconds);

  // The clock at log time `stamp` (s) and the odometry there (odom frame), as a robot's base sends
  // them.
  void PublishOdometry(double stamp, const Pose2& odometry);
  // A scan at its own stamp, its beams judged up to `range_max` m (the message's range_max).
  void PublishScan(const CarmenScan& scan, double range_max);

  // The poses navd published since the last Take (or since the link opened), in arrival order.
  std::vector<StampedPose> TakePoses();
  std::string pose_topic() const;

 private:
  struct Endpoints;
  ReplayLinkOptions options_;
  std::mutex mutex_;
  std::vector<StampedPose> poses_;
  std::unique_ptr<Endpoints> endpoints_;
};

}  // namespace navd::navctl
