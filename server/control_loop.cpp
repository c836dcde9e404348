#include "server/control_loop.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <limits>

namespace navd::server {

namespace {
// After a goal ends, a few zero commands make sure the robot heard "stop" on a lossy link; then
// navd goes quiet so other sources (teleop) may command the robot.
constexpr int kZeroCommandsAfterGoal = 5;
}  // namespace

ControlLoop::ControlLoop(const ControlLoopOptions& options, Clock& clock, DdsBridge& bridge,
                         localization::LocalizerSelector& localizer, navigation::NavigationExecutive& executive,
                         mapping::MapBuilder& map_builder, CameraPerception* camera)
    : options_(options),
      clock_(clock),
      bridge_(bridge),
      localizer_(localizer),
      executive_(executive),
      map_builder_(map_builder),
      camera_(camera) {}

ControlLoop::~ControlLoop() { Stop(); }

void ControlLoop::Start() {
  thread_ = std::thread([this] { Run(); });
}

void ControlLoop::Stop() {
  if (stop_.exchange(true)) return;  // already stopped
  if (thread_.joinable()) thread_.join();
  bridge_.StopRobot();
  spdlog::info("control loop: {}", timing_.Summary());
}

void ControlLoop::Run() {
  const double period = 1.0 / options_.rate;
  double next = clock_.Now();
  uint64_t tick = 0;
  double last_seen = next;
  auto last_advance = std::chrono::steady_clock::now();
  while (!stop_) {
    // Bounded waits keep the loop responsive to Stop() when simulated time stalls.
    // A microsecond early counts: clock stamps travel rounded to nanoseconds and `next` is a sum,
    // and navsim --lockstep, holding at a tick it takes as reached, must see it run.
    const bool reached = clock_.SleepUntil(next - 1e-6, 0.05);
    const double now = clock_.Now();
    const auto wall = std::chrono::steady_clock::now();
    if (now != last_seen) {
      last_seen = now;
      last_advance = wall;
    }
    if (now < next - 2 * period) next = now;  // the clock went back (simulator restarted)
    if (!reached) {
      // navsim --lockstep holds time until it hears this loop's next tick; a report sent before
      // its reader matched ours (DDS discovery) is lost, and both would wait: say it again.
      if (tick > 0) bridge_.PublishNextTick(next);
      // Time has not moved for longer than the sensor timeout: the simulator died or hangs, which
      // is stale sensors too. Its time is extrapolated so the navigator's stale timeout runs.
      const double frozen = std::chrono::duration<double>(wall - last_advance).count();
      if (frozen > options_.sensor_timeout) StaleTick(now + frozen);
      continue;
    }
    next += period;
    if (now - next > period) next = now + period;  // fell behind: do not burst
    Tick(tick++, now);
    bridge_.PublishNextTick(next);
  }
}

void ControlLoop::LogCrowdPlan(const WheelSpeeds& wheels, double now) {
  crowd_plans_seen_ = executive_.crowd().plans();
  const planning::CrowdTrajectory& plan = executive_.crowd().plan();
  const Pose2 pose = localizer_.Estimate().pose;
  std::string nearest = "nobody";
  double closest = std::numeric_limits<double>::infinity();
  const std::vector<navigation::TrackedPerson> people = executive_.people();
  for (const navigation::TrackedPerson& p : people) {
    const double d = Distance(p.position, pose.translation());
    if (d >= closest) continue;
    closest = d;
    const Point2 at = pose.inverse() * p.position;
    nearest = fmt::format("{:.2f} m, at ({:.2f}, {:.2f}) in the robot's frame, walking ({:.2f}, {:.2f}) m/s", d, at.x(),
                          at.y(), p.velocity.x(), p.velocity.y());
  }
  // Where the leg's path ahead ends (the plan's goal, unless the costmap hides it) and where the plan ends.
  const std::vector<Point2> ahead = executive_.navigator().PathAhead(executive_.crowd().options().lookahead);
  const Point2 path_end = ahead.empty() ? pose.translation() : ahead.back();
  const Point2 plan_end = plan.states.empty() ? pose.translation() : plan.states.back().position();
  spdlog::debug(
      "t={:.2f}s crowd plan {} at ({:.2f}, {:.2f}, {:.2f}): {} {:.2f} s to ({:.2f}, {:.2f}) for the path's "
      "({:.2f}, {:.2f}), cost {:.1f}, {} vertices; command {:.2f} m/s {:.2f} rad/s{}; {} people, nearest {}",
      now, crowd_plans_seen_, pose.x, pose.y, pose.theta,
      plan.escape    ? "escape"
      : plan.braking ? "braking"
                     : "driving",
      plan.states.empty() ? 0.0 : plan.states.back().t, plan_end.x(), plan_end.y(), path_end.x(), path_end.y(),
      plan.cost, plan.tree_size, 0.5 * (wheels.left + wheels.right), (wheels.right - wheels.left) / options_.wheel_base,
      executive_.crowd_steering() ? "" : " (not the crowd controller's)", people.size(), nearest);
}

void ControlLoop::StaleTick(double now) {
  const bool was_active = executive_.navigator().Status().active;
  executive_.Step(false, now);
  if (was_active) bridge_.PublishCommand({});
  bridge_.PublishStatus(executive_.navigator().Status(), localizer_.Estimate(), localizer_.name(), now);
}

std::optional<localization::ScanReading> ControlLoop::TakeScan(
    const std::optional<localization::OdometryReading>& newest_odometry,
    std::chrono::steady_clock::time_point tick_start, std::chrono::steady_clock::time_point& wall_arrival) {
  const uint64_t count = bridge_.scan_count();
  if (count == scans_seen_) return std::nullopt;
  wall_arrival = bridge_.last_scan_wall_arrival();
  std::optional<localization::ScanReading> scan = bridge_.LatestScan();
  // A scan waiting for the odometry of its instant is left for a later tick (or a newer scan).
  if (scan && scan_odometry_.Waits(scan->stamp, newest_odometry, tick_start)) return std::nullopt;
  scans_seen_ = count;
  return scan;
}

void ControlLoop::FeedOdometry(const std::optional<localization::OdometryReading>& newest_odometry,
                               const std::optional<localization::ScanReading>& scan) {
  for (const localization::OdometryReading& odom :
       scan_odometry_.Readings(newest_odometry, scan ? std::optional<double>(scan->stamp) : std::nullopt,
                               [this](double stamp) { return bridge_.OdometryAt(stamp); })) {
    localizer_.AddOdometry(odom);
    if (localizer_.odometry_jumps() != odometry_jumps_seen_) {
      odometry_jumps_seen_ = localizer_.odometry_jumps();
      spdlog::warn("odometry jumped to ({:.2f}, {:.2f}, {:.2f}) at t={:.2f}s: taken as no motion (jump {})",
                   odom.pose.x, odom.pose.y, odom.pose.theta, odom.stamp, odometry_jumps_seen_);
    }
  }
}

void ControlLoop::SubmitToMapping(const localization::ScanReading& scan, const Pose2& odom_at_scan) {
  // A mapping run takes the scan with the odometry of its own stamp (a robot turning at 1 rad/s
  // turns 0.05 rad in one control period, and under load ticks fall further apart), and the
  // localiser's pose carried to that stamp.
  const localization::PoseEstimate estimate = localizer_.Estimate();
  const Pose2 localised = estimate.pose * (bridge_.OdometryAt(estimate.stamp)->inverse() * odom_at_scan);
  mapping::RangeScan r{scan.ranges, scan.angle_min, scan.angle_increment, scan.stamp};
  if (scan.range_max > 0.0) r.range_max = scan.range_max;
  // Readings under the scanner's minimum (self-hits, glare) say nothing: NaN, where +inf would
  // be a no-return and clear along the beam.
  for (float& range : r.ranges)
    if (range < scan.range_min) range = std::numeric_limits<float>::quiet_NaN();
  map_builder_.Submit(odom_at_scan, localised, r);
}

std::optional<navigation::PeopleReport> ControlLoop::TakePeople() {
  if (bridge_.people_count() == people_seen_) return std::nullopt;
  people_seen_ = bridge_.people_count();
  std::optional<navigation::PeopleReport> people = bridge_.LatestPeople();
  // The count and the sample are read apart: a tick may find the one it took already.
  if (!people || people->stamp == people_stamp_) return std::nullopt;
  people_stamp_ = people->stamp;
  return people;
}

bool ControlLoop::SensorsFresh(double now) const {
  // A laser that has spoken and then gone silent is stale too; a robot without one is not. People
  // read from a detector are needed: silent, or never heard, the sensors are stale.
  const bool laser_fresh = !bridge_.scan_seen() || now - bridge_.last_scan_arrival() <= options_.sensor_timeout;
  const bool people_fresh = !bridge_.reads_people() || now - bridge_.last_people_arrival() <= options_.sensor_timeout;
  return laser_fresh && people_fresh && now - bridge_.last_odometry_arrival() <= options_.sensor_timeout;
}

void ControlLoop::LogChanges(const WheelSpeeds& wheels, const navigation::NavigationStatus& status, bool contact,
                             double now) {
  if (spdlog::should_log(spdlog::level::trace)) {
    // Every tick's command, with what it came from, to set beside navsim's trace of the truth.
    const localization::PoseEstimate e = localizer_.Estimate();
    spdlog::trace("t={:.2f}s tick at ({:.3f}, {:.3f}, {:.3f}): wheels {:.3f} {:.3f} m/s, {}, state {}{}{}{}", now,
                  e.pose.x, e.pose.y, e.pose.theta, wheels.left, wheels.right,
                  executive_.crowd_steering() ? "crowd controller" : "navigator",
                  navigation::NavigationStateName(status.feedback.state), contact ? ", bumper pressed" : "",
                  status.hold_reason.empty() ? "" : ": ", status.hold_reason);
  }
  if (status.feedback.behaviour != behaviour_ || status.hold_reason != hold_reason_) {
    // Why the robot does what it does, in the log as well as in the telemetry.
    const localization::PoseEstimate e = localizer_.Estimate();
    spdlog::info("t={:.2f}s at ({:.2f}, {:.2f}, {:.2f}) behaviour {}{}{}", now, e.pose.x, e.pose.y, e.pose.theta,
                 status.feedback.behaviour, status.hold_reason.empty() ? "" : ": ", status.hold_reason);
    behaviour_ = status.feedback.behaviour;
    hold_reason_ = status.hold_reason;
  }
  if (executive_.localization_lost() != was_lost_) {
    const localization::PoseEstimate e = localizer_.Estimate();
    was_lost_ = executive_.localization_lost();
    spdlog::info("t={:.2f}s pose {}: the scans fit the map at {:.2f}, position spread {:.2f} m", now,
                 was_lost_ ? "lost" : "found again", e.quality, e.PositionSpread());
  } else if (executive_.localization_losses() != losses_seen_) {
    const localization::PoseEstimate e = localizer_.Estimate();
    spdlog::info(
        "t={:.2f}s pose lost and found again: the localiser moved it to ({:.2f}, {:.2f}, {:.2f}), "
        "where the scans fit the map at {:.2f}",
        now, e.pose.x, e.pose.y, e.pose.theta, e.quality);
  }
  losses_seen_ = executive_.localization_losses();
  if (spdlog::should_log(spdlog::level::debug) && executive_.crowd().plans() != crowd_plans_seen_)
    LogCrowdPlan(wheels, now);
}

void ControlLoop::Tick(uint64_t tick, double now) {
  const auto tick_start = std::chrono::steady_clock::now();
  timing_.TickStarted(tick_start);
  const std::optional<localization::OdometryReading> newest_odometry = bridge_.LatestOdometry();
  std::chrono::steady_clock::time_point scan_wall_arrival;
  // The scan that arrived since the last tick.
  const std::optional<localization::ScanReading> scan = TakeScan(newest_odometry, tick_start, scan_wall_arrival);
  FeedOdometry(newest_odometry, scan);
  std::optional<Pose2> odom_at_scan;
  if (scan) {
    if (executive_.localization_active()) localizer_.AddScan(*scan);
    odom_at_scan = bridge_.OdometryAt(scan->stamp);
    if (map_builder_.active() && odom_at_scan) SubmitToMapping(*scan, *odom_at_scan);
  }
  // The people report that arrived since the last tick.
  const std::optional<navigation::PeopleReport> people = TakePeople();
  const bool was_active = executive_.navigator().Status().active || was_searching_;
  navigation::ExecutiveInputs inputs;
  inputs.sensors_fresh = SensorsFresh(now);
  inputs.contact = bridge_.Contact(options_.sensor_timeout);
  inputs.rear_contact_only = bridge_.RearContactOnly(options_.sensor_timeout);
  inputs.scans = scans_seen_;
  inputs.scan = scan ? &*scan : nullptr;
  inputs.scan_odometry = odom_at_scan;
  inputs.odometry = bridge_.OdometryAt(localizer_.Estimate().stamp);
  inputs.rear_free = bridge_.RearFree(options_.sensor_timeout);
  if (camera_) inputs.sensed_cells = camera_->Step(now);
  const std::vector<navigation::SonarEcho> sonar = bridge_.SonarEchoes(options_.sensor_timeout);
  inputs.sonar = &sonar;
  inputs.people = people ? &*people : nullptr;
  inputs.people_odometry = people ? bridge_.OdometryAt(people->stamp) : std::nullopt;
  if (people) {
    const auto odometry = bridge_.LatestOdometry();
    inputs.people_age = odometry ? std::clamp(odometry->stamp - people->stamp, 0.0, 1.0) : 0.0;
  }
  const WheelSpeeds wheels = executive_.Step(inputs, now);
  const navigation::NavigationStatus status = executive_.navigator().Status();
  LogChanges(wheels, status, inputs.contact, now);
  was_searching_ = executive_.searching();
  if (status.active || was_searching_) {
    bridge_.PublishCommand(ToTwist(wheels, options_.wheel_base));
    if (scan) timing_.CommandAfterScan(scan_wall_arrival, tick_start, std::chrono::steady_clock::now());
    zero_commands_left_ = kZeroCommandsAfterGoal;
  } else if (was_active || zero_commands_left_ > 0) {
    bridge_.PublishCommand({});
    zero_commands_left_ = was_active ? kZeroCommandsAfterGoal : zero_commands_left_ - 1;
  }
  const localization::PoseEstimate estimate = localizer_.Estimate();
  if (estimate.valid) bridge_.PublishPose(estimate, now);
  if (tick % 2 == 0) bridge_.PublishStatus(status, estimate, localizer_.name(), now);
}

}  // namespace navd::server
