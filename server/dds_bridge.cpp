#include "server/dds_bridge.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string_view>

#include "dds/conversions.h"
#include "dds/point_cloud2.h"
#include "dds/topics.h"
#include "services/common/error.h"
#include "services/localization/scan_points.h"

namespace navd::server {
namespace {

// nav_msgs/OccupancyGrid of `geometry`'s size and place with `cells` (row-major, one byte each).
nav_msgs::msg::dds_::OccupancyGrid_ GridMessage(const OccupancyGrid& geometry, const char* cells, double now) {
  nav_msgs::msg::dds_::OccupancyGrid_ m;
  m.header(dds::MakeHeader(now, "map"));
  m.info().map_load_time(dds::ToTime(now));
  m.info().resolution(static_cast<float>(geometry.resolution()));
  m.info().width(geometry.width());
  m.info().height(geometry.height());
  m.info().origin(dds::ToPose(Pose2{geometry.origin().x(), geometry.origin().y(), 0.0}));
  m.data().assign(cells, cells + geometry.cells().size());
  return m;
}

// Whether the n-th bad sample of a stream is logged: the 1st, 10th, 100th and every 1000th, so a
// sensor sending garbage at its rate does not flood the log.
bool WorthSaying(int n) { return n == 1 || n == 10 || n == 100 || n % 1000 == 0; }

}  // namespace

using dds::Reliability;

DdsBridge::DdsBridge(const dds::ParticipantOptions& options, const std::string& ns, SimClock* sim_clock,
                     const Clock& arrival_clock, const RobotDescription* encoders, const std::string& rear_range_frame,
                     const std::vector<double>& sonar_angles, bool people)
    : participant_(options), ns_(ns), arrival_clock_(arrival_clock), rear_range_frame_(rear_range_frame) {
  if (encoders) {
    wheel_odometry_ = std::make_unique<localization::WheelOdometry>(*encoders);
    joints_reader_ = std::make_unique<dds::Reader<sensor_msgs::msg::dds_::JointState_PubSubType>>(
        participant_, dds::TopicName(ns, dds::kJointStates), Reliability::kBestEffort,
        [this](const sensor_msgs::msg::dds_::JointState_& m) { OnJointState(m); }, 5);
  }
  if (sim_clock) {
    clock_reader_ = std::make_unique<dds::Reader<rosgraph_msgs::msg::dds_::Clock_PubSubType>>(
        participant_, dds::kClock, Reliability::kBestEffort,
        [sim_clock](const rosgraph_msgs::msg::dds_::Clock_& m) { sim_clock->Set(dds::FromTime(m.clock())); }, 1);
    next_tick_writer_ = std::make_unique<dds::Writer<rosgraph_msgs::msg::dds_::Clock_PubSubType>>(
        participant_, dds::TopicName(ns, dds::kNextTick), Reliability::kReliable, 1);
  }
  if (!encoders) {
    odom_reader_ = std::make_unique<dds::Reader<nav_msgs::msg::dds_::Odometry_PubSubType>>(
        participant_, dds::TopicName(ns, dds::kOdom), Reliability::kBestEffort,
        [this](const nav_msgs::msg::dds_::Odometry_& m) {
          last_odom_arrival_ = arrival_clock_.Now();
          Remember({dds::FromPose(m.pose().pose()), Eigen::Matrix3d::Zero(), dds::FromTime(m.header().stamp())});
        },
        5);
  }
  bumper_reader_ = std::make_unique<dds::Reader<navsim_msgs::msg::dds_::BumperState_PubSubType>>(
      participant_, dds::TopicName(ns, dds::kBumper), Reliability::kBestEffort,
      [this](const navsim_msgs::msg::dds_::BumperState_& m) {
        if (m.front() || m.rear()) last_contact_ = arrival_clock_.Now();
        if (m.front()) last_front_contact_ = arrival_clock_.Now();
      },
      2);
  if (!rear_range_frame.empty()) {
    ir_reader_ = std::make_unique<dds::Reader<sensor_msgs::msg::dds_::Range_PubSubType>>(
        participant_, dds::TopicName(ns, dds::kIr), Reliability::kBestEffort,
        [this](const sensor_msgs::msg::dds_::Range_& m) { OnRearRange(m); }, 8);
  }
  if (!sonar_angles.empty()) {
    for (double a : sonar_angles) sonar_.push_back({a});
    // A ring sends one message per sensor in a burst: the history holds a whole one.
    sonar_reader_ = std::make_unique<dds::Reader<sensor_msgs::msg::dds_::Range_PubSubType>>(
        participant_, dds::TopicName(ns, dds::kSonar), Reliability::kBestEffort,
        [this](const sensor_msgs::msg::dds_::Range_& m) { OnSonar(m); }, static_cast<int>(2 * sonar_angles.size()));
  }
  if (people) {
    people_reader_ = std::make_unique<dds::Reader<people_msgs::msg::dds_::People_PubSubType>>(
        participant_, dds::TopicName(ns, dds::kPeople), Reliability::kBestEffort,
        [this](const people_msgs::msg::dds_::People_& m) { OnPeople(m); }, 2);
  }
  scan_topic_ = dds::TopicName(ns, dds::kScan);
  scan_reader_ = std::make_unique<dds::Reader<sensor_msgs::msg::dds_::LaserScan_PubSubType>>(
      participant_, scan_topic_, Reliability::kBestEffort,
      [this](const sensor_msgs::msg::dds_::LaserScan_&) {
        last_scan_arrival_ = arrival_clock_.Now();
        last_scan_wall_ = std::chrono::steady_clock::now().time_since_epoch().count();
      },
      2);
  cmd_writer_ = std::make_unique<dds::Writer<geometry_msgs::msg::dds_::Twist_PubSubType>>(
      participant_, dds::TopicName(ns, dds::kCmdVel), Reliability::kReliable, 5);
  status_writer_ = std::make_unique<dds::Writer<navd_msgs::msg::dds_::NavStatus_PubSubType>>(
      participant_, dds::TopicName(ns, dds::kNavStatus), Reliability::kReliable, 5);
  pose_writer_ = std::make_unique<dds::Writer<geometry_msgs::msg::dds_::PoseWithCovarianceStamped_PubSubType>>(
      participant_, dds::TopicName(ns, dds::kPose), Reliability::kReliable, 5);
  map_writer_ = std::make_unique<dds::Writer<nav_msgs::msg::dds_::OccupancyGrid_PubSubType>>(
      participant_, dds::TopicName(ns, dds::kMap), Reliability::kReliable, 1, true);
  costmap_writer_ = std::make_unique<dds::Writer<nav_msgs::msg::dds_::OccupancyGrid_PubSubType>>(
      participant_, dds::TopicName(ns, dds::kCostmap), Reliability::kReliable, 1, true);
}

void DdsBridge::OnJointState(const sensor_msgs::msg::dds_::JointState_& m) {
  std::lock_guard<std::mutex> lock(wheel_mutex_);
  const auto reading = wheel_odometry_->AddWheelAngles(m.position(), dds::FromTime(m.header().stamp()));
  if (!reading) return;  // wrong wheel count or non-finite angles: never integrated
  wheel_reading_ = reading;
  Remember(*reading);
  ++wheel_count_;
  last_odom_arrival_ = arrival_clock_.Now();
}

void DdsBridge::OnRearRange(const sensor_msgs::msg::dds_::Range_& m) {
  if (m.header().frame_id() != rear_range_frame_) return;
  // REP 117: +inf (or anything past max_range) is "nothing in range", -inf and readings at
  // min_range (a Sharp IR's 0.1 m) something that close or closer; NaN says nothing.
  if (std::isnan(m.range())) return;
  double r = m.range() == -std::numeric_limits<float>::infinity() ? 0.0 : std::min<double>(m.range(), m.max_range());
  if (r <= m.min_range()) r = 0.0;
  rear_range_ = r;
  last_rear_arrival_ = arrival_clock_.Now();
}

void DdsBridge::OnSonar(const sensor_msgs::msg::dds_::Range_& m) {
  const std::string& frame = m.header().frame_id();
  constexpr std::string_view kPrefix = "sonar_";
  if (frame.rfind(kPrefix, 0) != 0) return;
  size_t index = 0;
  try {
    index = std::stoul(frame.substr(kPrefix.size()));
  } catch (const std::exception&) {
    return;
  }
  if (index >= sonar_.size() || !(m.range() >= 0.0f)) return;
  std::lock_guard<std::mutex> lock(sonar_mutex_);
  SonarSlot& s = sonar_[index];
  // ROS: +inf, or anything at or past max_range, is "nothing in range".
  s.echo = std::isfinite(m.range()) && m.range() < m.max_range();
  s.range = m.range();
  s.arrival = arrival_clock_.Now();
}

void DdsBridge::OnPeople(const people_msgs::msg::dds_::People_& m) {
  if (InBaseLink(m)) {
    last_people_arrival_ = arrival_clock_.Now();
    return;
  }
  // The sensors are stale meanwhile.
  const int n = ++bad_people_;
  if (WorthSaying(n))
    spdlog::warn("people report ignored ({} so far): frame_id '{}' is not base_link", n, m.header().frame_id());
}

void DdsBridge::ReadCamera() {
  if (cloud_reader_) return;
  cloud_reader_ = std::make_unique<dds::Reader<sensor_msgs::msg::dds_::PointCloud2_PubSubType>>(
      participant_, dds::TopicName(ns_, dds::kCameraPoints), Reliability::kBestEffort,
      [this](const sensor_msgs::msg::dds_::PointCloud2_& m) {
        try {
          auto cloud = std::make_shared<CameraCloud>();
          cloud->points = dds::DecodeXyzCloud(m);
          cloud->stamp = dds::FromTime(m.header().stamp());
          std::lock_guard<std::mutex> lock(cloud_mutex_);
          cloud_ = std::move(cloud);
          ++cloud_count_;
        } catch (const Error& e) {
          const int n = ++bad_clouds_;
          if (WorthSaying(n))
            spdlog::warn("{} cloud ignored ({} so far): {}", dds::TopicName(ns_, dds::kCameraPoints), n, e.what());
        }
      },
      1);
}

std::shared_ptr<const DdsBridge::CameraCloud> DdsBridge::LatestCloud() const {
  std::lock_guard<std::mutex> lock(cloud_mutex_);
  return cloud_;
}

void DdsBridge::PublishCostmap(const OccupancyGrid& geometry, const std::vector<int8_t>& cells, double now) {
  if (cells.size() != geometry.cells().size()) return;
  costmap_writer_->Write(GridMessage(geometry, reinterpret_cast<const char*>(cells.data()), now));
}

std::optional<localization::OdometryReading> DdsBridge::LatestOdometry() const {
  if (wheel_odometry_) {
    std::lock_guard<std::mutex> lock(wheel_mutex_);
    return wheel_reading_;
  }
  const auto m = odom_reader_->Latest();
  if (!m) return std::nullopt;
  localization::OdometryReading r;
  r.pose = dds::FromPose(m->pose().pose());
  r.stamp = dds::FromTime(m->header().stamp());
  r.covariance = dds::FromCovariance6(m->pose().covariance());
  return r;
}

std::optional<localization::ScanReading> DdsBridge::LatestScan() const {
  const auto m = scan_reader_->Latest();
  if (!m) return std::nullopt;
  const std::string bad =
      localization::ScanGeometryError(m->ranges().size(), m->angle_min(), m->angle_max(), m->angle_increment());
  if (!bad.empty()) {
    const int n = ++bad_scans_;
    if (WorthSaying(n)) spdlog::warn("{}: scan ignored ({} so far): {}", scan_topic_, n, bad);
    return std::nullopt;
  }
  localization::ScanReading s;
  s.ranges = m->ranges();
  s.angle_min = m->angle_min();
  s.angle_increment = m->angle_increment();
  s.range_min = m->range_min();
  s.range_max = m->range_max();
  s.stamp = dds::FromTime(m->header().stamp());
  return s;
}

bool DdsBridge::InBaseLink(const people_msgs::msg::dds_::People_& m) {
  const std::string& frame = m.header().frame_id();
  return frame == "base_link" || frame.ends_with("/base_link");
}

std::optional<navigation::PeopleReport> DdsBridge::LatestPeople() const {
  if (!people_reader_) return std::nullopt;
  const auto m = people_reader_->Latest();
  if (!m) return std::nullopt;
  if (!InBaseLink(*m)) return std::nullopt;
  navigation::PeopleReport r;
  r.stamp = dds::FromTime(m->header().stamp());
  for (const people_msgs::msg::dds_::Person_& p : m->people())
    r.people.push_back({p.name(), {p.position().x(), p.position().y()}, {p.velocity().x(), p.velocity().y()}});
  return r;
}

void DdsBridge::Remember(const localization::OdometryReading& reading) {
  if (!reading.pose.finite() || !std::isfinite(reading.stamp)) return;  // never interpolated from
  std::lock_guard<std::mutex> lock(history_mutex_);
  history_.Add(history_filter_.Filter(reading));
}

std::optional<Pose2> DdsBridge::OdometryAt(double stamp) const {
  std::lock_guard<std::mutex> lock(history_mutex_);
  if (history_.empty()) return std::nullopt;
  return history_.At(stamp);
}

bool DdsBridge::Contact(double within) const { return arrival_clock_.Now() - last_contact_.load() <= within; }

bool DdsBridge::RearContactOnly(double within) const {
  return Contact(within) && arrival_clock_.Now() - last_front_contact_.load() > within;
}

double DdsBridge::RearFree(double within) const {
  if (arrival_clock_.Now() - last_rear_arrival_.load() > within) return std::numeric_limits<double>::infinity();
  return rear_range_.load();
}

std::vector<navigation::SonarEcho> DdsBridge::SonarEchoes(double within) const {
  std::vector<navigation::SonarEcho> out;
  const double now = arrival_clock_.Now();
  std::lock_guard<std::mutex> lock(sonar_mutex_);
  for (const SonarSlot& s : sonar_) {
    if (s.echo && now - s.arrival <= within) out.push_back({s.angle, s.range});
  }
  return out;
}

void DdsBridge::PublishCommand(const Twist2& twist) {
  geometry_msgs::msg::dds_::Twist_ m;
  m.linear().x(twist.v);
  m.angular().z(twist.omega);
  cmd_writer_->Write(m);
}

void DdsBridge::PublishPose(const localization::PoseEstimate& pose, double now) {
  geometry_msgs::msg::dds_::PoseWithCovarianceStamped_ m;
  // Stamped with the time the estimate describes (its newest odometry), as AMCL stamps amcl_pose
  // with its scan's time, so that it can be compared with ground truth of the same instant.
  m.header().stamp(dds::ToTime(pose.stamp > 0.0 ? pose.stamp : now));
  m.header().frame_id("map");
  m.pose().pose(dds::ToPose(pose.pose));
  m.pose().covariance(dds::ToCovariance6(pose.covariance));
  pose_writer_->Write(m);
}

void DdsBridge::PublishMap(const OccupancyGrid& grid, double now) {
  map_writer_->Write(GridMessage(grid, reinterpret_cast<const char*>(grid.cells().data()), now));
}

void DdsBridge::PublishNextTick(double next_tick) {
  if (!next_tick_writer_) return;
  rosgraph_msgs::msg::dds_::Clock_ m;
  m.clock(dds::ToTime(next_tick));
  next_tick_writer_->Write(m);
}

void DdsBridge::StopRobot() {
  PublishCommand({});
  cmd_writer_->WaitForAcknowledgments(1.0);
}

void DdsBridge::PublishStatus(const navigation::NavigationStatus& status, const localization::PoseEstimate& pose,
                              const std::string& localizer, double now) {
  navd_msgs::msg::dds_::NavStatus_ m;
  m.header().stamp(dds::ToTime(now));
  m.header().frame_id("map");
  m.x(pose.pose.x);
  m.y(pose.pose.y);
  m.theta(pose.pose.theta);
  for (int i = 0; i < 9; ++i) m.covariance()[i] = pose.covariance(i / 3, i % 3);
  m.state(static_cast<uint8_t>(status.feedback.state));
  m.active(status.active);
  m.sensors_stale(status.sensors_stale);
  m.goal_x(status.goal.pose.x);
  m.goal_y(status.goal.pose.y);
  m.distance_remaining(status.active ? status.feedback.distance_remaining : 0.0);
  m.localizer(localizer);
  m.quality(pose.quality);
  const navigation::NavigationFeedback& f = status.feedback;
  m.behaviour(f.behaviour);
  m.mission_index(f.mission_index);
  m.mission_count(f.mission_count);
  m.laps_completed(f.laps_completed);
  m.distance_travelled(f.distance_travelled);
  m.eta(status.active ? f.eta : 0.0);
  for (const navigation::ProcessUtility& u : f.utilities) {
    navd_msgs::msg::dds_::ProcessUtility_ p;
    p.name(u.name);
    p.motor(u.kind == navigation::ProcessKind::kMotor);
    p.utility(u.utility);
    p.gamma(u.gamma);
    p.active(u.active);
    m.utilities().push_back(p);
  }
  m.danger(f.danger);
  for (const planning::MovingBody& b : f.moving_obstacles) {
    navd_msgs::msg::dds_::MovingObstacle_ o;
    o.x(b.position.x());
    o.y(b.position.y());
    o.vx(b.velocity.x());
    o.vy(b.velocity.y());
    o.radius(b.radius);
    m.moving_obstacles().push_back(o);
  }
  status_writer_->Write(m);
}

}  // namespace navd::server
