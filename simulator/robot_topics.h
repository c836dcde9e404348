#pragma once
// One simulated robot's DDS endpoints, in ROS 2's topic layout under rt/<robot>/: scan, sonar, ir,
// odom, joint_states, bumper, people, camera points, ground_truth and sim/status out; cmd_vel and
// cmd_accel in, and navd/next_tick under --lockstep. Commands arrive on DDS threads and wait until
// the simulation thread applies them between steps. Metres, radians, seconds of simulated time.
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

#include "dds/participant.h"
#include "geometry_msgsPubSubTypes.h"
#include "nav_msgsPubSubTypes.h"
#include "navsim_msgsPubSubTypes.h"
#include "people_msgsPubSubTypes.h"
#include "rosgraph_msgsPubSubTypes.h"
#include "sensor_msgsPubSubTypes.h"
#include "simulator/lockstep_gate.h"
#include "simulator/simulation.h"

namespace navd::sim {

class RobotTopics {
 public:
  // gate: when given (--lockstep), the robot's navd/next_tick reports go to it as robot `index`.
  RobotTopics(dds::Participant& p, const SimulatedRobot& robot, LockstepGate* gate, size_t index);

  // Whether a reader takes this robot's depth images (asked of DDS every few hundred steps).
  bool camera_watched() const { return camera_ && camera_->matched() > 0; }

  // The commands that arrived since the last call, to robot `index` of the simulation.
  void ApplyCommands(Simulation& simulation, size_t index);

  // The readings of one step at simulated time t; the ground truth when `truth`, sim/status when
  // `status` or when the robot's collision count changed.
  void Publish(double t, const SimulatedRobot& robot, const RobotReadings& in, bool truth, bool status,
               double real_time_factor);

 private:
  template <typename WriterT>
  void PublishRanges(double t, const std::string& kind, uint8_t radiation, const RangeSensorArray& array,
                     const std::vector<float>& ranges, WriterT& writer);
  void PublishPeople(double t, const std::vector<PersonReading>& people);
  void PublishJoints(double t, const MobileBase& base);
  void PublishStatus(double t, const SimulatedRobot& robot, double real_time_factor);

  std::string ns_;
  dds::Writer<sensor_msgs::msg::dds_::LaserScan_PubSubType> scan_;
  dds::Writer<sensor_msgs::msg::dds_::Range_PubSubType> sonar_, ir_;
  dds::Writer<nav_msgs::msg::dds_::Odometry_PubSubType> odom_;
  dds::Writer<sensor_msgs::msg::dds_::JointState_PubSubType> joints_;
  dds::Writer<navsim_msgs::msg::dds_::BumperState_PubSubType> bumper_;
  dds::Writer<nav_msgs::msg::dds_::Odometry_PubSubType> truth_;
  dds::Writer<navsim_msgs::msg::dds_::SimStatus_PubSubType> status_;
  std::unique_ptr<dds::Writer<people_msgs::msg::dds_::People_PubSubType>> people_;       // with a people sensor
  std::unique_ptr<dds::Writer<sensor_msgs::msg::dds_::PointCloud2_PubSubType>> camera_;  // with a depth camera
  std::mutex mutex_;
  std::optional<BodyTwist> velocity_;
  std::optional<std::pair<double, double>> accel_;  // m/s², rad/s²
  dds::Reader<geometry_msgs::msg::dds_::Twist_PubSubType> cmd_vel_;
  dds::Reader<geometry_msgs::msg::dds_::Accel_PubSubType> cmd_accel_;
  std::unique_ptr<dds::Reader<rosgraph_msgs::msg::dds_::Clock_PubSubType>> next_tick_;
  sensor_msgs::msg::dds_::LaserScan_ scan_msg_;
  uint32_t reported_collisions_ = 0;
};

}  // namespace navd::sim
