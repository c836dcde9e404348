#pragma once
// libnavclient's DDS side: subscribes navd's telemetry (rt/navd/status) and, when a simulator
// runs, its truth (rt/ground_truth, rt/sim/status). Newest sample of each, plus optional callbacks.
#include <memory>
#include <optional>

#include "dds/participant.h"
#include "geometry_msgsPubSubTypes.h"
#include "nav_msgsPubSubTypes.h"
#include "navd_msgsPubSubTypes.h"
#include "navsim_msgsPubSubTypes.h"

namespace navd {

struct TelemetryOptions {
  dds::ParticipantOptions dds;
  std::string robot_namespace;
};

class Telemetry {
 public:
  using StatusCallback = std::function<void(const navd_msgs::msg::dds_::NavStatus_&)>;
  using TruthCallback = std::function<void(const nav_msgs::msg::dds_::Odometry_&)>;
  using PoseCallback = std::function<void(const geometry_msgs::msg::dds_::PoseWithCovarianceStamped_&)>;
  using WorldCallback = std::function<void(const navsim_msgs::msg::dds_::WorldState_&)>;
  // The callbacks run on DDS threads, once per sample. on_world: the simulator's bodies
  // (rt/sim/world_state), subscribed only when given.
  explicit Telemetry(const TelemetryOptions& options, StatusCallback on_status = {}, TruthCallback on_truth = {},
                     PoseCallback on_pose = {}, WorldCallback on_world = {});

  std::optional<navd_msgs::msg::dds_::NavStatus_> LatestStatus() const { return status_->Latest(); }
  std::optional<navsim_msgs::msg::dds_::SimStatus_> LatestSimStatus() const { return sim_status_->Latest(); }
  std::optional<nav_msgs::msg::dds_::Odometry_> LatestGroundTruth() const { return truth_->Latest(); }
  std::optional<geometry_msgs::msg::dds_::PoseWithCovarianceStamped_> LatestPose() const { return pose_->Latest(); }
  uint64_t pose_count() const { return pose_->count(); }
  // navd's map on rt/<ns>/map (nav_msgs/OccupancyGrid), every couple of seconds.
  std::optional<nav_msgs::msg::dds_::OccupancyGrid_> LatestMap() const { return map_->Latest(); }
  uint64_t map_count() const { return map_->count(); }
  uint64_t status_count() const { return status_->count(); }
  uint64_t sim_status_count() const { return sim_status_->count(); }

  // Blocks until a simulator status sample newer than those seen so far arrives, or timeout.
  std::optional<navsim_msgs::msg::dds_::SimStatus_> WaitForSimStatus(double timeout) const;

 private:
  dds::Participant participant_;
  std::unique_ptr<dds::Reader<navd_msgs::msg::dds_::NavStatus_PubSubType>> status_;
  std::unique_ptr<dds::Reader<navsim_msgs::msg::dds_::SimStatus_PubSubType>> sim_status_;
  std::unique_ptr<dds::Reader<nav_msgs::msg::dds_::Odometry_PubSubType>> truth_;
  std::unique_ptr<dds::Reader<geometry_msgs::msg::dds_::PoseWithCovarianceStamped_PubSubType>> pose_;
  std::unique_ptr<dds::Reader<nav_msgs::msg::dds_::OccupancyGrid_PubSubType>> map_;
  std::unique_ptr<dds::Reader<navsim_msgs::msg::dds_::WorldState_PubSubType>> world_;
};

}  // namespace navd
