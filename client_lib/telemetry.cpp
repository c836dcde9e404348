#include "client_lib/telemetry.h"

#include <chrono>
#include <thread>

#include "dds/topics.h"

namespace navd {

Telemetry::Telemetry(const TelemetryOptions& o, StatusCallback on_status, TruthCallback on_truth, PoseCallback on_pose,
                     WorldCallback on_world)
    : participant_(o.dds) {
  using dds::Reliability;
  status_ = std::make_unique<dds::Reader<navd_msgs::msg::dds_::NavStatus_PubSubType>>(
      participant_, dds::TopicName(o.robot_namespace, dds::kNavStatus), Reliability::kReliable, std::move(on_status));
  sim_status_ = std::make_unique<dds::Reader<navsim_msgs::msg::dds_::SimStatus_PubSubType>>(
      participant_, dds::TopicName(o.robot_namespace, dds::kSimStatus), Reliability::kReliable);
  truth_ = std::make_unique<dds::Reader<nav_msgs::msg::dds_::Odometry_PubSubType>>(
      participant_, dds::TopicName(o.robot_namespace, dds::kGroundTruth), Reliability::kBestEffort,
      std::move(on_truth));
  pose_ = std::make_unique<dds::Reader<geometry_msgs::msg::dds_::PoseWithCovarianceStamped_PubSubType>>(
      participant_, dds::TopicName(o.robot_namespace, dds::kPose), Reliability::kReliable, std::move(on_pose));
  map_ = std::make_unique<dds::Reader<nav_msgs::msg::dds_::OccupancyGrid_PubSubType>>(
      participant_, dds::TopicName(o.robot_namespace, dds::kMap), Reliability::kReliable);
  if (on_world) {
    world_ = std::make_unique<dds::Reader<navsim_msgs::msg::dds_::WorldState_PubSubType>>(
        participant_, dds::kWorldState, Reliability::kBestEffort, std::move(on_world), 50);
  }
}

std::optional<navsim_msgs::msg::dds_::SimStatus_> Telemetry::WaitForSimStatus(double timeout) const {
  const uint64_t seen = sim_status_->count();
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
  while (std::chrono::steady_clock::now() < end) {
    if (sim_status_->count() > seen) return sim_status_->Latest();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return std::nullopt;
}

}  // namespace navd
