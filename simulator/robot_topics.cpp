#include "simulator/robot_topics.h"

#include <spdlog/spdlog.h>

#include <cmath>

#include "dds/conversions.h"
#include "dds/point_cloud2.h"
#include "dds/topics.h"

namespace navd::sim {
namespace {

namespace msgs_geo = geometry_msgs::msg::dds_;
namespace msgs_sim = navsim_msgs::msg::dds_;
namespace msgs_sensor = sensor_msgs::msg::dds_;
using dds::MakeHeader;
using dds::Reliability;
using dds::TopicName;

nav_msgs::msg::dds_::Odometry_ MakeOdometry(double t, const Pose2& pose, const BodyTwist& twist,
                                            const Eigen::Matrix3d& cov, const std::string& frame) {
  return dds::MakeOdometry(t, pose, twist.vx, twist.vy, twist.omega, cov, frame);
}

}  // namespace

RobotTopics::RobotTopics(dds::Participant& p, const SimulatedRobot& robot, LockstepGate* gate, size_t index)
    : ns_(robot.name()),
      scan_(p, TopicName(ns_, dds::kScan), Reliability::kBestEffort, 5),
      sonar_(p, TopicName(ns_, dds::kSonar), Reliability::kBestEffort, 32),
      ir_(p, TopicName(ns_, dds::kIr), Reliability::kBestEffort, 8),
      odom_(p, TopicName(ns_, dds::kOdom), Reliability::kBestEffort, 5),
      joints_(p, TopicName(ns_, dds::kJointStates), Reliability::kBestEffort, 5),
      bumper_(p, TopicName(ns_, dds::kBumper), Reliability::kBestEffort, 5),
      truth_(p, TopicName(ns_, dds::kGroundTruth), Reliability::kBestEffort, 5),
      status_(p, TopicName(ns_, dds::kSimStatus), Reliability::kReliable, 10),
      cmd_vel_(
          p, TopicName(ns_, dds::kCmdVel), Reliability::kReliable,
          [this](const msgs_geo::Twist_& m) {
            if (!std::isfinite(m.linear().x()) || !std::isfinite(m.linear().y()) || !std::isfinite(m.angular().z())) {
              spdlog::warn("navsim: ignored a {} with non-finite values", TopicName(ns_, dds::kCmdVel));
              return;
            }
            std::lock_guard<std::mutex> lock(mutex_);
            velocity_ = BodyTwist{m.linear().x(), m.linear().y(), m.angular().z()};
            accel_.reset();
          }),
      cmd_accel_(p, TopicName(ns_, dds::kCmdAccel), Reliability::kReliable, [this](const msgs_geo::Accel_& m) {
        if (!std::isfinite(m.linear().x()) || !std::isfinite(m.angular().z())) {
          spdlog::warn("navsim: ignored a {} with non-finite values", TopicName(ns_, dds::kCmdAccel));
          return;
        }
        std::lock_guard<std::mutex> lock(mutex_);
        accel_ = std::make_pair(m.linear().x(), m.angular().z());
        velocity_.reset();
      }) {
  if (const auto& l = robot.laser()) {
    scan_msg_.angle_min(static_cast<float>(l->angle_min()));
    scan_msg_.angle_max(static_cast<float>(l->angle_max()));
    scan_msg_.angle_increment(static_cast<float>(l->increment()));
    scan_msg_.scan_time(static_cast<float>(1.0 / l->description().rate));
    scan_msg_.time_increment(static_cast<float>(1.0 / l->description().rate / l->description().beams));
    scan_msg_.range_min(static_cast<float>(l->description().range_min));
    scan_msg_.range_max(static_cast<float>(l->description().range_max));
  }
  if (robot.spec().camera) {
    camera_ = std::make_unique<dds::Writer<msgs_sensor::PointCloud2_PubSubType>>(
        p, TopicName(ns_, dds::kCameraPoints), Reliability::kBestEffort, 2, /*large=*/true);
  }
  if (robot.spec().people) {
    people_ = std::make_unique<dds::Writer<people_msgs::msg::dds_::People_PubSubType>>(p, TopicName(ns_, dds::kPeople),
                                                                                       Reliability::kBestEffort, 2);
  }
  if (gate) {
    next_tick_ = std::make_unique<dds::Reader<rosgraph_msgs::msg::dds_::Clock_PubSubType>>(
        p, TopicName(ns_, dds::kNextTick), Reliability::kReliable,
        [gate, index](const rosgraph_msgs::msg::dds_::Clock_& m) { gate->Report(index, dds::FromTime(m.clock())); }, 1);
  }
}

void RobotTopics::ApplyCommands(Simulation& simulation, size_t index) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (velocity_) simulation.Command(index, *velocity_);
  if (accel_) simulation.CommandAcceleration(index, accel_->first, accel_->second);
  velocity_.reset();
  accel_.reset();
}

void RobotTopics::Publish(double t, const SimulatedRobot& robot, const RobotReadings& in, bool truth, bool status,
                          double real_time_factor) {
  const MobileBase& base = robot.base();
  // Odometry first: a reader pairs each scan with the odometry of its instant, and waits for it.
  if (in.odom) odom_.Write(MakeOdometry(t, base.odom_pose(), base.odom_twist(), base.odom_covariance(), "odom"));
  if (in.scan) {
    scan_msg_.header(MakeHeader(t, "base_scan"));
    scan_msg_.ranges(*in.scan);
    scan_.Write(scan_msg_);
  }
  if (in.camera && camera_) camera_->Write(dds::EncodeXyzCloud(*in.camera, t, "camera_depth_optical_frame"));
  if (in.sonar) PublishRanges(t, "sonar", 0, *robot.sonar(), *in.sonar, sonar_);
  if (in.ir) PublishRanges(t, "ir", 1, *robot.ir(), *in.ir, ir_);
  if (in.people && people_) PublishPeople(t, *in.people);
  if (in.encoders) PublishJoints(t, base);
  if (in.bumper) {
    msgs_sim::BumperState_ b;
    b.header(MakeHeader(t, "base_link"));
    b.front(robot.bumper().front);
    b.rear(robot.bumper().rear);
    bumper_.Write(b);
  }
  if (truth) truth_.Write(MakeOdometry(t, base.true_pose(), base.true_twist(), Eigen::Matrix3d::Zero(), "map"));
  if (status || robot.collisions() != reported_collisions_) PublishStatus(t, robot, real_time_factor);
}

template <typename WriterT>
void RobotTopics::PublishRanges(double t, const std::string& kind, uint8_t radiation, const RangeSensorArray& array,
                                const std::vector<float>& ranges, WriterT& writer) {
  const auto& d = array.description();
  for (size_t i = 0; i < ranges.size(); ++i) {
    msgs_sensor::Range_ r;
    r.header(MakeHeader(t, kind + "_" + std::to_string(i)));
    r.radiation_type(radiation);
    r.field_of_view(static_cast<float>(d.cone));
    r.min_range(static_cast<float>(d.range_min));
    r.max_range(static_cast<float>(d.range_max));
    r.range(ranges[i]);
    writer.Write(r);
  }
}

void RobotTopics::PublishPeople(double t, const std::vector<PersonReading>& people) {
  people_msgs::msg::dds_::People_ m;
  m.header(MakeHeader(t, "base_link"));
  for (const PersonReading& r : people) {
    people_msgs::msg::dds_::Person_ person;
    person.name("person " + std::to_string(r.id));
    person.position().x(r.position.x());
    person.position().y(r.position.y());
    person.velocity().x(r.velocity.x());
    person.velocity().y(r.velocity.y());
    person.reliability(1.0);
    m.people().push_back(std::move(person));
  }
  people_->Write(m);
}

void RobotTopics::PublishJoints(double t, const MobileBase& base) {
  msgs_sensor::JointState_ j;
  j.header(MakeHeader(t, "base_link"));
  const auto angles = base.wheel_angles();
  const auto speeds = base.wheel_speeds();
  for (size_t i = 0; i < angles.size(); ++i) {
    j.name().push_back(angles.size() == 2 ? (i == 0 ? "left_wheel" : "right_wheel") : "wheel_" + std::to_string(i + 1));
    j.position().push_back(angles[i]);
    j.velocity().push_back(speeds[i] / base.description().wheel_radius);
  }
  joints_.Write(j);
}

void RobotTopics::PublishStatus(double t, const SimulatedRobot& robot, double real_time_factor) {
  const MobileBase& base = robot.base();
  msgs_sim::SimStatus_ s;
  s.header(MakeHeader(t, "map"));
  s.x(base.true_pose().x);
  s.y(base.true_pose().y);
  s.theta(base.true_pose().theta);
  s.collisions(robot.collisions());
  s.in_collision(robot.in_collision());
  s.distance_travelled(base.distance_travelled());
  s.real_time_factor(real_time_factor);
  status_.Write(s);
  reported_collisions_ = robot.collisions();
}

}  // namespace navd::sim
