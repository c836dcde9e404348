#pragma once
// The per-robot control loop: at a fixed rate of the daemon's clock it localises (newest odometry
// into the localiser), decides (one navigation step, stopping on stale sensors) and commands
// (cmd_vel), and publishes telemetry at half the rate.
#include <atomic>
#include <chrono>
#include <optional>
#include <thread>

#include "server/camera_perception.h"
#include "server/control_loop_timing.h"
#include "server/dds_bridge.h"
#include "services/localization/localizer_selector.h"
#include "services/localization/scan_odometry_pairing.h"
#include "services/mapping/map_builder.h"
#include "services/navigation/navigation_executive.h"

namespace navd::server {

struct ControlLoopOptions {
  double rate = 20.0;           // Hz
  double sensor_timeout = 0.3;  // s
  double wheel_base = 0.33;     // m, to turn wheel speeds into a twist
};

class ControlLoop {
 public:
  ControlLoop(const ControlLoopOptions& options, Clock& clock, DdsBridge& bridge,
              localization::LocalizerSelector& localizer, navigation::NavigationExecutive& executive,
              mapping::MapBuilder& map_builder, CameraPerception* camera = nullptr);
  ~ControlLoop();
  void Start();
  // Stops the loop and sends the robot a zero command.
  void Stop();

 private:
  void Run();
  // One step at clock time `now` (seconds).
  void Tick(uint64_t tick, double now);
  // The scan that arrived since the last tick (its wall arrival in `wall_arrival`), unless it waits
  // for the odometry of its instant.
  std::optional<localization::ScanReading> TakeScan(const std::optional<localization::OdometryReading>& newest_odometry,
                                                    std::chrono::steady_clock::time_point tick_start,
                                                    std::chrono::steady_clock::time_point& wall_arrival);
  // The odometry up to the scan's stamp (or the newest) into the localiser, logging jumps.
  void FeedOdometry(const std::optional<localization::OdometryReading>& newest_odometry,
                    const std::optional<localization::ScanReading>& scan);
  // The scan into a running mapping run, at the odometry of its stamp.
  void SubmitToMapping(const localization::ScanReading& scan, const Pose2& odom_at_scan);
  // The people report that arrived since the last tick, once.
  std::optional<navigation::PeopleReport> TakePeople();
  // Odometry, and the laser and people detector once heard, within sensor_timeout of `now`.
  bool SensorsFresh(double now) const;
  // The log's account of a tick: its command at trace level, changes of behaviour and of the
  // pose's loss at info, the crowd's plans at debug.
  void LogChanges(const WheelSpeeds& wheels, const navigation::NavigationStatus& status, bool contact, double now);
  // Runs when the clock has not advanced for sensor_timeout wall seconds; `now` is extrapolated.
  void StaleTick(double now);
  // At debug level (SPDLOG_LEVEL=debug), each new plan of the crowd controller: what it chose and
  // the nearest person it knew, so a street run's contacts can be traced.
  void LogCrowdPlan(const WheelSpeeds& wheels, double now);

  ControlLoopOptions options_;
  Clock& clock_;
  DdsBridge& bridge_;
  localization::LocalizerSelector& localizer_;
  int odometry_jumps_seen_ = 0;
  bool was_searching_ = false;  // the wake-up behaviour drove the robot last tick
  bool was_lost_ = false;       // the executive counted the pose lost last tick (for the log)
  uint64_t losses_seen_ = 0;    // the executive's count of losses last tick (for the log)
  navigation::NavigationExecutive& executive_;
  mapping::MapBuilder& map_builder_;
  CameraPerception* camera_;  // null: no depth camera
  std::atomic<bool> stop_{false};
  std::thread thread_;
  ControlLoopTiming timing_;
  int zero_commands_left_ = 0;
  uint64_t scans_seen_ = 0;
  localization::ScanOdometryPairing scan_odometry_;
  uint64_t people_seen_ = 0;
  double people_stamp_ = -1.0;           // of the last people report handed on
  std::string behaviour_, hold_reason_;  // at the last tick, to log changes
  uint64_t crowd_plans_seen_ = 0;        // the crowd controller's plans already in the debug log
};

}  // namespace navd::server
