#pragma once
// navd's side of DDS: keeps the newest odometry, scan and clock sample (the listeners only copy),
// and publishes velocity commands and navd_msgs telemetry.
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "dds/participant.h"
#include "geometry_msgsPubSubTypes.h"
#include "nav_msgsPubSubTypes.h"
#include "navd_msgsPubSubTypes.h"
#include "navsim_msgsPubSubTypes.h"
#include "people_msgsPubSubTypes.h"
#include "rosgraph_msgsPubSubTypes.h"
#include "sensor_msgsPubSubTypes.h"
#include "services/common/clock.h"
#include "services/common/diff_drive.h"
#include "services/localization/localizer.h"
#include "services/localization/odometry_history.h"
#include "services/localization/odometry_jump_filter.h"
#include "services/localization/wheel_odometry.h"
#include "services/navigation/navigator.h"
#include "services/navigation/reported_people.h"
#include "services/navigation/sonar_reflex.h"

namespace navd::server {

class DdsBridge {
 public:
  // sim_clock: when given, rt/clock samples drive it. arrival_clock stamps odometry arrival for
  // the staleness check. encoders: when given, odometry is computed from the robot's wheel
  // encoders (rt/<ns>/joint_states, with this robot's kinematics) instead of read from rt/<ns>/odom.
  // rear_range_frame: the frame_id of the rear-facing range sensor on rt/<ns>/ir (seed 000's rear
  // Sharp IR, ir_2 on navsim's robots); empty: none. sonar_angles: the mounting angle (rad, robot
  // frame) of sensor sonar_<i> on rt/<ns>/sonar; empty: the sonar is not read. people: read a
  // people detector's reports on rt/<ns>/people (people_msgs/People in base_link).
  DdsBridge(const dds::ParticipantOptions& options, const std::string& robot_namespace, SimClock* sim_clock,
            const Clock& arrival_clock, const RobotDescription* encoders = nullptr,
            const std::string& rear_range_frame = "", const std::vector<double>& sonar_angles = {},
            bool people = false);

  // The newest odometry reading, if any, and when (arrival clock) it arrived.
  std::optional<localization::OdometryReading> LatestOdometry() const;
  double last_odometry_arrival() const { return last_odom_arrival_.load(); }
  uint64_t odometry_count() const { return wheel_odometry_ ? wheel_count_.load() : odom_reader_->count(); }
  // The odometry pose at `stamp`, interpolated from every reading that arrived (not only those
  // the control loop saw: under load its ticks fall far apart in simulated time), jumps taken out
  // (a reset odom frame is no motion for a mapping run either); nullopt before the first reading.
  std::optional<Pose2> OdometryAt(double stamp) const;

  // The newest scan and how many have arrived (to tell a new one from the last).
  std::optional<localization::ScanReading> LatestScan() const;
  uint64_t scan_count() const { return scan_reader_->count(); }
  // Arrival clock time of the newest scan; very negative before the first.
  double last_scan_arrival() const { return last_scan_arrival_.load(); }
  bool scan_seen() const { return last_scan_arrival_.load() > -1e8; }
  // Wall (steady clock) time the newest scan arrived, for the control loop's latency figures.
  std::chrono::steady_clock::time_point last_scan_wall_arrival() const {
    return std::chrono::steady_clock::time_point(std::chrono::steady_clock::duration(last_scan_wall_.load()));
  }

  // Whether a bumper reported contact within the last `within` seconds of the arrival clock.
  bool Contact(double within = 0.5) const;
  // Whether only the rear bumper reported contact within the last `within` seconds.
  bool RearContactOnly(double within = 0.5) const;
  // Metres free behind the robot's rim by the rear range sensor (its maximum range when it sees
  // nothing); infinity without a reading in the last `within` seconds.
  double RearFree(double within = 0.5) const;
  // The sonar ring's echoes that arrived within the last `within` seconds, sensors that heard
  // nothing (max_range or beyond) left out; empty without a sonar.
  std::vector<navigation::SonarEcho> SonarEchoes(double within = 0.5) const;

  // Whether people reports are read (the constructor's `people`).
  bool reads_people() const { return people_reader_ != nullptr; }
  // The newest people report and how many have arrived; nullopt without one (or when not read).
  // Reports in another frame than base_link are dropped with a warning.
  std::optional<navigation::PeopleReport> LatestPeople() const;
  uint64_t people_count() const { return people_reader_ ? people_reader_->count() : 0; }
  // Arrival clock time of the newest people report in base_link; very negative before the first.
  double last_people_arrival() const { return last_people_arrival_.load(); }

  // From now on, the depth camera's clouds on rt/<ns>/camera/points (sensor_msgs/PointCloud2 in
  // its optical frame): the newest, decoded, and how many arrived. A cloud whose layout the
  // PointCloud2 rules refuse is dropped with a warning.
  struct CameraCloud {
    std::vector<Eigen::Vector3f> points;  // optical frame, metres
    double stamp = 0.0;                   // s
  };
  void ReadCamera();
  std::shared_ptr<const CameraCloud> LatestCloud() const;
  uint64_t cloud_count() const { return cloud_count_.load(); }

  void PublishCommand(const Twist2& twist);
  // Sends a zero command and waits (bounded) until the robot side acknowledged it; for shutdown.
  void StopRobot();
  void PublishStatus(const navigation::NavigationStatus& status, const localization::PoseEstimate& pose,
                     const std::string& localizer, double now);
  // The pose estimate on rt/<ns>/pose, as AMCL publishes amcl_pose (x, y, yaw covariance in ROS order).
  void PublishPose(const localization::PoseEstimate& pose, double now);
  // Under simulated time: the control loop finished its tick and needs nothing until `next_tick`
  // (s), on rt/<ns>/navd/next_tick, which navsim --lockstep waits for. Nothing under system time.
  void PublishNextTick(double next_tick);
  // A map on rt/<ns>/map in nav_msgs/OccupancyGrid layout (ROS 2 viewers show it), map frame.
  void PublishMap(const OccupancyGrid& grid, double now);
  // The costmap navd plans on (sensed obstacles included) on rt/<ns>/navd/costmap, as Nav2
  // publishes its costmaps: 0 free to 99, 100 lethal, -1 unknown; `cells` row-major in that scale.
  void PublishCostmap(const OccupancyGrid& geometry, const std::vector<int8_t>& cells, double now);

 private:
  void Remember(const localization::OdometryReading& reading);
  // The readers' callbacks, on DDS threads.
  void OnJointState(const sensor_msgs::msg::dds_::JointState_& m);
  void OnRearRange(const sensor_msgs::msg::dds_::Range_& m);
  void OnSonar(const sensor_msgs::msg::dds_::Range_& m);
  void OnPeople(const people_msgs::msg::dds_::People_& m);
  // Whether a people report is in base_link (or <ns>/base_link).
  static bool InBaseLink(const people_msgs::msg::dds_::People_& m);

  dds::Participant participant_;
  std::string ns_;
  const Clock& arrival_clock_;
  std::string rear_range_frame_;  // the frame_id of the rear range sensor's readings on rt/<ns>/ir
  std::atomic<double> last_odom_arrival_{-1e9};
  // Odometry from the wheel encoders, when navd computes it (--odometry encoders).
  std::unique_ptr<localization::WheelOdometry> wheel_odometry_;
  mutable std::mutex wheel_mutex_;
  std::optional<localization::OdometryReading> wheel_reading_;
  mutable std::mutex history_mutex_;
  localization::OdometryHistory history_{256};
  localization::OdometryJumpFilter history_filter_;
  std::atomic<uint64_t> wheel_count_{0};
  std::string scan_topic_;
  mutable std::atomic<int> bad_scans_{0};
  std::atomic<double> last_contact_{-1e9};
  std::atomic<double> last_front_contact_{-1e9};
  std::atomic<double> rear_range_{0.0};
  std::atomic<double> last_rear_arrival_{-1e9};
  std::atomic<double> last_scan_arrival_{-1e9};
  std::atomic<std::chrono::steady_clock::rep> last_scan_wall_{0};
  struct SonarSlot {
    double angle = 0.0;
    double range = 0.0;
    bool echo = false;
    double arrival = -1e9;
  };
  mutable std::mutex sonar_mutex_;
  std::vector<SonarSlot> sonar_;
  std::atomic<double> last_people_arrival_{-1e9};
  std::atomic<int> bad_people_{0};
  mutable std::mutex cloud_mutex_;
  std::shared_ptr<const CameraCloud> cloud_;
  std::atomic<uint64_t> cloud_count_{0};
  std::atomic<int> bad_clouds_{0};
  std::unique_ptr<dds::Writer<geometry_msgs::msg::dds_::Twist_PubSubType>> cmd_writer_;
  std::unique_ptr<dds::Writer<navd_msgs::msg::dds_::NavStatus_PubSubType>> status_writer_;
  std::unique_ptr<dds::Writer<geometry_msgs::msg::dds_::PoseWithCovarianceStamped_PubSubType>> pose_writer_;
  std::unique_ptr<dds::Writer<nav_msgs::msg::dds_::OccupancyGrid_PubSubType>> map_writer_;
  std::unique_ptr<dds::Writer<rosgraph_msgs::msg::dds_::Clock_PubSubType>> next_tick_writer_;
  std::unique_ptr<dds::Writer<nav_msgs::msg::dds_::OccupancyGrid_PubSubType>> costmap_writer_;
  // The readers last: destroyed first, so that no callback runs on the state above once it is gone.
  std::unique_ptr<dds::Reader<nav_msgs::msg::dds_::Odometry_PubSubType>> odom_reader_;
  std::unique_ptr<dds::Reader<sensor_msgs::msg::dds_::JointState_PubSubType>> joints_reader_;
  std::unique_ptr<dds::Reader<sensor_msgs::msg::dds_::LaserScan_PubSubType>> scan_reader_;
  std::unique_ptr<dds::Reader<rosgraph_msgs::msg::dds_::Clock_PubSubType>> clock_reader_;
  std::unique_ptr<dds::Reader<navsim_msgs::msg::dds_::BumperState_PubSubType>> bumper_reader_;
  std::unique_ptr<dds::Reader<sensor_msgs::msg::dds_::Range_PubSubType>> ir_reader_;
  std::unique_ptr<dds::Reader<sensor_msgs::msg::dds_::Range_PubSubType>> sonar_reader_;
  std::unique_ptr<dds::Reader<people_msgs::msg::dds_::People_PubSubType>> people_reader_;
  std::unique_ptr<dds::Reader<sensor_msgs::msg::dds_::PointCloud2_PubSubType>> cloud_reader_;
};

}  // namespace navd::server
