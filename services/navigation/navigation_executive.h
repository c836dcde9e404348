#pragma once
// navd's executive, after Wahde et al. (seed 000): each control step it measures the state
// variables (the cognitive processes update what the others read), lets the utility functions pick
// one motor behaviour, runs it, and passes its command through the command filters
// (docs/architecture.md, "The executive's control step"). Missions come in as goals, waypoint lists
// or deliveries; LegPlanner checks them and plans each leg. The gRPC adapter and the control loop
// both talk to this class only.
#include <atomic>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "services/common/clock.h"
#include "services/common/error.h"
#include "services/localization/localizer.h"
#include "services/navigation/command_filter.h"
#include "services/navigation/avoidance_behaviour.h"
#include "services/navigation/brain_layout.h"
#include "services/navigation/crowd_controller.h"
#include "services/navigation/crowd_steering.h"
#include "services/navigation/delivery_scheduler.h"
#include "services/navigation/emergency_stop.h"
#include "services/navigation/leg_planner.h"
#include "services/navigation/localization_watch.h"
#include "services/navigation/long_term_memory.h"
#include "services/navigation/mission_requests.h"
#include "services/navigation/moving_obstacle_avoidance.h"
#include "services/navigation/moving_obstacle_detection.h"
#include "services/navigation/moving_obstacle_detector.h"
#include "services/navigation/navigator.h"
#include "services/navigation/people_tracking.h"
#include "services/navigation/person_tracker.h"
#include "services/navigation/reported_people.h"
#include "services/navigation/sensed_obstacles.h"
#include "services/navigation/served_map_caster.h"
#include "services/navigation/recovery_behaviour.h"
#include "services/navigation/sonar_reflex.h"
#include "services/navigation/speed_zone_filter.h"
#include "services/navigation/utility_decision_maker.h"
#include "services/navigation/wake_up.h"
#include "services/planning/planning_engine.h"

namespace navd::navigation {

// Seed 000's moving obstacles: the detection process (section 4.4), the avoidance behaviour
// (section 4.5), and Delta, the range within which detected obstacles enter the leg plans (the
// grid navigation "will not deliberately plan a path that intersects a nearby moving obstacle").
struct MovingObstacleOptions {
  MovingObstacleDetectorOptions detection;
  MovingObstacleAvoidanceOptions avoidance;
  double planning_range = 3.0;  // m
  double replan_period = 1.0;   // s between checks that a confirmed obstacle lies across the path
  // A bumper pressed while a detected obstacle's (enlarged) disc is this close to the robot's rim
  // is that obstacle's doing.
  double touch_gap = 0.15;  // m
  // While navigating, the forward speed is capped so the robot could stop guard_margin short of
  // a moving tracked obstacle ahead at guard_deceleration (a third of the seed robot's wheel limit, for the
  // command's latency).
  double guard_margin = 0.10;       // m
  double guard_deceleration = 0.7;  // m/s^2
  double guard_min_speed = 0.1;     // m/s: slower tracked obstacles are left to the plans
  // ... and never faster than it could stop scan_guard_margin short of what the laser sees ahead.
  double scan_guard_margin = 0.05;  // m
  // Turning in place is never quite in place: each wheel misses its speed a little, so the centre
  // creeps along the heading. With something this near the rim in front (a cart that came up to
  // the robot and waits there; in the front half, or among people within 60 degrees of the
  // heading), that creep touches it; the robot
  // keeps only the straight part of its command then, as the avoidance behaviour waits rather
  // than turn (its turn_clearance). When the straight part cannot go on either, it turns while
  // backing at turn_guard_backing, if the way back is free for turn_guard_backing_room.
  double turn_guard_gap = 0.05;           // m
  double turn_guard_backing = 0.03;       // m/s
  double turn_guard_backing_room = 0.05;  // m
};

// What the control loop measured this step.
struct ExecutiveInputs {
  bool sensors_fresh = true;       // odometry (and the laser) arrived recently
  bool contact = false;            // a bumper is pressed
  bool rear_contact_only = false;  // ... and it is the rear one only
  uint64_t scans = 0;              // scans that have arrived so far (0: not counted)
  // The scan that arrived since the last step, if one did.
  const localization::ScanReading* scan = nullptr;
  // The robot's odometry pose (odometry frame) when that scan was taken, and at the localiser's
  // estimate's stamp. With both, the scan is placed where the robot was when it was taken (a robot
  // turning at 1.5 rad/s turns 0.1 rad in the 0.07 s a scan may wait: half a metre at 5 m), and
  // people are tracked in the odometry frame, which does not jump when the localiser corrects
  // itself. Without them, the estimate's pose and the map frame.
  std::optional<Pose2> scan_odometry = std::nullopt;
  std::optional<Pose2> odometry = std::nullopt;
  // m free behind the robot's rim by its rear range sensor; infinity without one.
  double rear_free = std::numeric_limits<double>::infinity();
  // The sonar ring's recent echoes (sensors that heard nothing left out); null: no sonar.
  const std::vector<SonarEcho>* sonar = nullptr;
  // The people report that arrived since the last step, if one did (PeopleAwareOptions::kReports),
  // the robot's odometry pose at its stamp (without it, the estimate's pose), and how old it was
  // (s, by the robot's clock: the newest odometry's stamp less the report's).
  const PeopleReport* people = nullptr;
  std::optional<Pose2> people_odometry = std::nullopt;
  double people_age = 0.0;
  // The cells a 3-D obstacle layer holds now (the depth camera's: what the laser's plane misses),
  // map frame; null: no such layer. The plans go round them, the replanning watches them, and the
  // scan guard and the avoidance take them as returns of the laser.
  std::shared_ptr<const std::vector<Point2>> sensed_cells = nullptr;
};

class NavigationExecutive {
 public:
  // Throws navd::Error(kInvalidArgument) when the brain lacks a 'navigation' motor behaviour or
  // names a state variable navd does not measure (contact, sensors_stale, localization_lost).
  NavigationExecutive(planning::PlanningEngine& planning, localization::Localizer& localizer, const Clock& clock,
                      const NavigatorOptions& options, const UtilityBrainOptions& brain = DefaultBrainOptions(),
                      const LocalizationWatchOptions& watch = {}, const MovingObstacleOptions& moving = {},
                      const PeopleAwareOptions& people = {});

  // Throws navd::Error: kInvalidArgument (non-finite goal, goal outside the map or blocked,
  // unknown planner; field named), kFailedPrecondition (no pose yet, or a mission active without
  // preempt), kNotFound (no path). Returns the mission id.
  uint64_t Navigate(const NavigateRequest& request, const planning::StopRequested& stop = {});
  // Checks every waypoint (and every leg between them) before starting; errors name
  // `waypoints[i]`.
  uint64_t FollowWaypoints(const MissionRequest& request, const planning::StopRequested& stop = {});
  // The schedule a delivery mission would drive, from the current pose; errors name tasks[i].
  DeliverySchedule PlanDeliveries(const DeliveryRequest& request, const planning::StopRequested& stop = {});
  // Plans the schedule and starts it (the stops as waypoints; the start again last with
  // return_to_start). Returns the mission id.
  uint64_t Deliver(const DeliveryRequest& request, DeliverySchedule& schedule,
                   const planning::StopRequested& stop = {});
  bool Cancel(uint64_t goal_id = 0) { return navigator_.Cancel(goal_id); }
  void Pause() { navigator_.Pause(clock_.Now()); }
  void Resume() { navigator_.Resume(clock_.Now()); }

  // One control step at daemon clock time `now` (seconds); returns the wheel command (m/s).
  WheelSpeeds Step(const ExecutiveInputs& inputs, double now);
  WheelSpeeds Step(bool sensors_fresh, double now) { return Step(ExecutiveInputs{sensors_fresh, false}, now); }

  const Navigator& navigator() const { return navigator_; }
  // Book chapter 7's crowd controller, and whether it drove the last step (for the debug log).
  const CrowdController& crowd() const { return crowd_.controller(); }
  bool crowd_steering() const { return crowd_.steering(); }
  bool localization_lost() const { return watch_.lost(); }
  // Times the pose has been lost since start: declared lost by the watch, or relocated by the
  // localiser on its own to where the scans fit (lost and found within a scan or two).
  uint64_t localization_losses() const { return watch_.losses(); }
  // The wake-up behaviour has the robot (its pose is lost): it turns the robot in place whether or
  // not a mission is active, since an idle robot that stands still can never be found again.
  bool searching() const { return layout_.wake_up >= 0 && static_cast<long>(brain_.active_motor()) == layout_.wake_up; }
  // Whether the localisation process runs (laser corrections of the pose); the control loop asks
  // before it hands the localiser a scan.
  bool localization_active() const {
    return layout_.localization >= 0 && brain_.active(static_cast<size_t>(layout_.localization));
  }
  // The detection process's danger level (its confirmed obstacles go out in the feedback).
  double danger() const;
  // The served map is being built as the robot drives (exploration): state variable
  // map_building, which switches the moving-obstacle detection off in the default brain, since a
  // scan compared with a map that has not seen every wall, and redraws after each loop closure,
  // finds "moving" obstacles everywhere (measured: evasive manoeuvres in an empty warehouse).
  void SetMapBuilding(bool building) { map_building_ = building; }
  // Speed limits by zone (the world's speed_zones, or a client's): every motor behaviour's command
  // is capped by them, and the feedback carries the limit. Thread-safe.
  void SetSpeedZones(SpeedZones zones);
  SpeedZones speed_zones() const;
  // The people tracked now (map frame), with people-aware navigation on. Thread-safe.
  std::vector<TrackedPerson> people() const;
  // The served map's version the localisers match scans against (long-term memory); 0 while a
  // hand-over is under way. Control thread.
  uint64_t localizer_map_version() const;

 private:
  uint64_t StartMission(const Mission& mission, const std::string& planner, bool preempt,
                        const planning::StopRequested& stop);
  // The winning motor behaviour's command, before the command filters, and who produced it.
  struct Decision {
    WheelSpeeds wheels;
    CommandSource source = CommandSource::kOther;
    bool tracking_obstacles = false;  // the moving-obstacle detection ran this step
  };
  Decision Decide(const ExecutiveInputs& in, double now);
  // The cognitive processes' step: what the sensors show, placed on the map (the scan's returns,
  // tracked obstacles and people, the sonar's unexplained echoes); forgotten while the pose is lost.
  void Perceive(const ExecutiveInputs& in, const localization::PoseEstimate& estimate, bool detecting, double now);
  // The brain's state variables (kMeasured) this step.
  std::vector<double> MeasureStateVariables(const ExecutiveInputs& in, const localization::PoseEstimate& estimate,
                                            bool detecting, double now) const;
  // The navigation behaviour: a recovery when stuck, the drive back onto the grid when off it,
  // else the mission's leg (replanned when something lies across it) with the crowd controller
  // among people or seed 004's sonar reflex.
  Decision Navigation(const ExecutiveInputs& in, const Pose2& pose, bool fresh, bool detecting, double now);
  std::optional<WheelSpeeds> Recover(const Pose2& pose, double rear_free, bool fresh, double now);
  // Runs motor behaviour `behaviour` (brain process `process`): its command, with what it says
  // passed on to the navigator's feedback, the brain and the plans; nullopt when it leaves the
  // robot to navigation.
  std::optional<WheelSpeeds> Carry(MotorBehaviour& behaviour, size_t process, const MotorInputs& in);
  // Seed 004's sonar reflex summed with the navigation behaviour's command.
  WheelSpeeds Reflex(const WheelSpeeds& wheels, const ExecutiveInputs& in, const Pose2& pose);
  // The echoes the reflex answers, within remember_within: with only_unexplained, those nearer than
  // both the map and the laser's last scan say anything is along the sensor's cone.
  std::vector<SonarEcho> Stimuli(const std::vector<SonarEcho>& echoes, const Pose2& pose) const;
  // Keeps `stimuli` as obstacle discs for the plans (map frame), forgetting old ones.
  void RememberSonar(const std::vector<SonarEcho>& stimuli, const Pose2& pose, double now);
  // What the avoidance behaviour sees: the last scan's points and the rear clearance.
  AvoidanceSensing Sensing(const Pose2& pose, double rear_free) const;
  // The rims of the moving tracked obstacles, now and within a second, in the frame of a robot at
  // `pose` (TrackedObstacleGuard's points).
  std::vector<Point2> MovingRims(const Pose2& pose) const;

  planning::PlanningEngine& planning_;
  localization::Localizer& localizer_;
  const Clock& clock_;
  Navigator navigator_;
  UtilityDecisionMaker brain_;
  BrainLayout layout_;
  LocalizationWatch watch_;
  std::atomic<bool> map_building_{false};
  MovingObstacleOptions moving_;
  // The cognitive processes and what they found, which the behaviours, filters and plans read.
  ServedMapCaster map_caster_;
  MovingObstacleDetection obstacle_detection_;
  PeopleAwareOptions people_;
  PeopleTracking people_tracking_;
  SensedObstacles sensed_;
  LongTermMemory memory_process_;
  CrowdSteering crowd_;
  WheelSpeeds last_wheels_;  // the last command of Step (the crowd controller starts from it)
  SonarReflex reflex_;
  bool reflex_acted_ = false;       // the reflex answered a stimulus this step
  std::vector<SonarEcho> stimuli_;  // this step's unexplained echoes
  // The motor behaviours other than navigation (which is this class's own, with its recoveries).
  EmergencyStop stop_behaviour_;
  WakeUp wake_up_behaviour_;
  AvoidanceBehaviour avoidance_behaviour_;
  RecoveryBehaviour recovery_;
  LegPlanner legs_;
  double last_blocked_check_ = -1e9;
  double last_step_ = -1.0;
  // Run on every command, in the order the constructor adds them.
  CommandFilterChain filters_;
  std::shared_ptr<SpeedZoneFilter> speed_zones_;
};

}  // namespace navd::navigation
