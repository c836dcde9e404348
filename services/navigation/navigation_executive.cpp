#include "services/navigation/navigation_executive.h"

#include <cmath>
#include <limits>

#include "services/common/error.h"
#include "services/localization/scan_points.h"
#include "services/navigation/leg_planner.h"
#include "services/navigation/surroundings_sensing.h"
#include "services/navigation/scan_guard.h"
#include "services/navigation/sonar_stimuli.h"
#include "services/navigation/tracked_obstacle_guard.h"

namespace navd::navigation {

namespace {

// The utility term process `name` keeps while its manoeuvre runs; 0 without such a process.
double GammaOnActivation(const UtilityDecisionMaker& brain, const char* name) {
  const long k = brain.FindProcess(name);
  return k >= 0 ? brain.options().processes[static_cast<size_t>(k)].gamma_on_activation : 0.0;
}

}  // namespace

NavigationExecutive::NavigationExecutive(planning::PlanningEngine& planning, localization::Localizer& localizer,
                                         const Clock& clock, const NavigatorOptions& options,
                                         const UtilityBrainOptions& brain, const LocalizationWatchOptions& watch,
                                         const MovingObstacleOptions& moving, const PeopleAwareOptions& people)
    : planning_(planning),
      localizer_(localizer),
      clock_(clock),
      navigator_(options),
      brain_(brain),
      layout_(BrainLayout::Of(brain_)),
      watch_(localizer, watch),
      moving_(moving),
      map_caster_(planning.maps()),
      obstacle_detection_(moving.detection),
      people_(people),
      people_tracking_(people),
      memory_process_(planning.maps(), localizer),
      crowd_(people.control, people.person_radius),
      reflex_(options.reflex),
      stop_behaviour_([&] {
        EmergencyStopOptions o;
        o.robot_radius = moving.detection.robot_radius;
        o.min_clearance = moving.avoidance.min_clearance;
        return o;
      }()),
      wake_up_behaviour_(watch_, options.follower.wheel_base),
      avoidance_behaviour_(moving.avoidance, GammaOnActivation(brain_, "moving_obstacle_avoidance"),
                           [this] { return obstacle_detection_.nearest_frontal(); }),
      recovery_(options.recovery, options.follower.wheel_base),
      legs_(planning, navigator_, obstacle_detection_, sensed_,
            LegPlannerOptions{moving.detection.robot_radius, moving.planning_range, options.reentry}) {
  // The command filters, in the order they act on the winning behaviour's command: the guards on
  // what the sensors see ahead first, then the speed zones, which cap whatever is left.
  const double radius = moving_.detection.robot_radius;
  filters_.Add(std::make_shared<TrackedObstacleGuard>(
      TrackedObstacleGuardOptions{radius, moving_.guard_margin, moving_.guard_deceleration}));
  filters_.Add(std::make_shared<ScanGuard>(
      ScanGuardOptions{radius, moving_.scan_guard_margin, moving_.guard_deceleration, moving_.turn_guard_gap,
                       moving_.turn_guard_backing, moving_.turn_guard_backing_room}));
  speed_zones_ = std::make_shared<SpeedZoneFilter>(radius, SpeedZoneOptions{});
  filters_.Add(speed_zones_);
}

uint64_t NavigationExecutive::Navigate(const NavigateRequest& r, const planning::StopRequested& stop) {
  return StartMission(MissionOf(r), r.planner, r.preempt, stop);
}

uint64_t NavigationExecutive::FollowWaypoints(const MissionRequest& r, const planning::StopRequested& stop) {
  return StartMission(MissionOf(r), r.planner, r.preempt, stop);
}

DeliverySchedule NavigationExecutive::PlanDeliveries(const DeliveryRequest& r, const planning::StopRequested& stop) {
  CheckDeliveryTasks(r);
  const localization::PoseEstimate estimate = localizer_.Estimate();
  if (!estimate.valid) {
    throw Error(ErrorCode::kFailedPrecondition, "no pose estimate yet: navd has not received odometry");
  }
  return PlanDeliverySchedule(planning_, estimate.pose.translation(), r, stop);
}

uint64_t NavigationExecutive::Deliver(const DeliveryRequest& r, DeliverySchedule& schedule,
                                      const planning::StopRequested& stop) {
  schedule = PlanDeliveries(r, stop);
  return FollowWaypoints(WaypointsOf(schedule, r, localizer_.Estimate().pose.translation()), stop);
}

uint64_t NavigationExecutive::StartMission(const Mission& mission, const std::string& planner, bool preempt,
                                           const planning::StopRequested& stop) {
  const localization::PoseEstimate estimate = localizer_.Estimate();
  if (!estimate.valid) {
    throw Error(ErrorCode::kFailedPrecondition, "no pose estimate yet: navd has not received odometry");
  }
  return legs_.StartMission(mission, planner, preempt, estimate.pose, clock_.Now(), stop);
}

uint64_t NavigationExecutive::localizer_map_version() const { return memory_process_.localizer_map_version(); }

std::vector<TrackedPerson> NavigationExecutive::people() const {
  return people_tracking_.People(people_tracking_.empty() ? 0.0 : clock_.Now());
}

WheelSpeeds NavigationExecutive::Reflex(const WheelSpeeds& wheels, const ExecutiveInputs& in, const Pose2& pose) {
  const std::optional<double> bearing = navigator_.SubgoalBearing(pose);
  if (!in.sonar || !bearing || !reflex_.options().enabled) return wheels;
  const ReflexResponse response = reflex_.Respond(stimuli_, *bearing);
  if (response.level == 0) return wheels;
  reflex_acted_ = true;
  navigator_.SetReflex(std::string(SonarGroupName(response.group)) + " level " + std::to_string(response.level));
  const PathFollowerParams& f = navigator_.options().follower;
  return SonarReflex::Blend(wheels, *bearing, response, f.k_p, f.max_wheel_speed);
}

std::vector<SonarEcho> NavigationExecutive::Stimuli(const std::vector<SonarEcho>& echoes, const Pose2& pose) const {
  if (!reflex_.options().only_unexplained) return echoes;
  // A map being built changes every few scans and lacks what it has not seen: the laser alone says.
  const std::shared_ptr<const RayCaster> map = map_building_ ? nullptr : map_caster_.Get();
  return UnexplainedEchoes(echoes, pose, moving_.detection.robot_radius, sensed_.LocalPoints(pose),
                           map ? &map->grid() : nullptr, reflex_);
}

void NavigationExecutive::RememberSonar(const std::vector<SonarEcho>& stimuli, const Pose2& pose, double now) {
  const SonarReflexOptions& o = reflex_.options();
  const double rim = moving_.detection.robot_radius;
  for (const SonarEcho& e : stimuli) {
    const Point2 dir(std::cos(e.angle), std::sin(e.angle));
    sensed_.Remember(pose * Point2((rim + e.range) * dir), std::max(0.05, e.range * std::tan(o.sensor_cone / 2.0)),
                     now);
  }
}

AvoidanceSensing NavigationExecutive::Sensing(const Pose2& pose, double rear_free) const {
  // The served map as it is now (a map being built changes; the detector's copy may be older).
  const auto map = planning_.maps().Get();
  return SenseSurroundings(pose, moving_.detection.robot_radius, sensed_.LocalPoints(pose), map ? &map->grid : nullptr,
                           rear_free, obstacle_detection_.candidates(), obstacle_detection_.confirmed());
}

double NavigationExecutive::danger() const { return obstacle_detection_.danger(); }

std::optional<WheelSpeeds> NavigationExecutive::Carry(MotorBehaviour& behaviour, size_t process,
                                                      const MotorInputs& in) {
  const std::optional<MotorCommand> c = behaviour.Act(in);
  if (!c) return std::nullopt;
  if (c->touched) {
    // Nav2's bumper layer: what the robot drove into goes into the plans (the laser and the map
    // show nothing there, or the leg would not have led into it).
    sensed_.Remember(c->touched->at, c->touched->radius, in.now);
    navigator_.NoteContact(c->touched->at, in.now);
  }
  if (c->gamma) brain_.SetGamma(process, *c->gamma);
  navigator_.Hold(in.pose, in.now, c->state, c->status, in.fresh);
  return c->wheels;
}

WheelSpeeds NavigationExecutive::Step(const ExecutiveInputs& in, double now) {
  reflex_acted_ = false;
  const Decision decision = Decide(in, now);
  if (!reflex_acted_) navigator_.SetReflex("");
  const localization::PoseEstimate estimate = localizer_.Estimate();
  const Pose2 pose = estimate.pose;
  CommandContext context;
  context.source = decision.source;
  context.pose_valid = estimate.valid;
  context.pose = pose;
  context.among_people = people_.enabled;
  context.tracking_obstacles = decision.tracking_obstacles;
  context.returns = [&] { return sensed_.LocalPoints(pose); };
  context.moving_rims = [&] { return MovingRims(pose); };
  context.rear_room = [&] { return Sensing(pose, in.rear_free).rear_free; };
  last_wheels_ = filters_.Apply(decision.wheels, context);
  navigator_.SetSpeedLimit(speed_zones_->last_limit());
  return last_wheels_;
}

void NavigationExecutive::SetSpeedZones(SpeedZones zones) { speed_zones_->SetZones(std::move(zones)); }

SpeedZones NavigationExecutive::speed_zones() const { return speed_zones_->zones(); }

void NavigationExecutive::Perceive(const ExecutiveInputs& in, const localization::PoseEstimate& estimate,
                                   bool detecting, double now) {
  // Where the robot was when the scan was taken (map frame).
  Pose2 scan_pose = estimate.pose;
  if (estimate.valid && in.odometry && in.scan_odometry) {
    const Pose2 map_from_odometry = estimate.pose * in.odometry->inverse();
    scan_pose = map_from_odometry * *in.scan_odometry;
    people_tracking_.SetMapFromOdometry(map_from_odometry);
  }
  if (in.sensed_cells) sensed_.SetLayerCells(in.sensed_cells);
  const bool placed = estimate.valid && !watch_.lost();  // what the sensors show can be put on the map
  if (in.scan && placed) {
    // The avoidance's and the recoil's free ways and the scan guard read these whether or not
    // detection runs (it is off while a map is being built).
    std::vector<Point2> points = localization::ScanEndPoints(*in.scan, 0);
    for (Point2& p : points) p = scan_pose * p;
    sensed_.SetScanReturns(std::move(points));
  }
  if (in.scan && placed && detecting) obstacle_detection_.Update(*in.scan, scan_pose, now, map_caster_.Get());
  const bool reports = people_.source == PeopleAwareOptions::Source::kReports;
  if (people_.enabled && !reports && in.scan && placed)
    people_tracking_.TrackScan(*in.scan, scan_pose, now, map_caster_.Get());
  if (people_.enabled && reports && in.people && placed) {
    // Without a laser nothing else keeps the map's place in the odometry frame.
    if (in.odometry) people_tracking_.SetMapFromOdometry(estimate.pose * in.odometry->inverse());
    people_tracking_.Report(*in.people, in.people_odometry, estimate.pose, now - in.people_age);
  }
  sensed_.Forget(now, reflex_.options().memory);
  stimuli_.clear();
  if (in.sonar && placed && reflex_.options().enabled) {
    stimuli_ = Stimuli(*in.sonar, estimate.pose);
    RememberSonar(stimuli_, estimate.pose, now);
  }
  // Detections made from a wrong pose are in the wrong place.
  if (watch_.lost() || !detecting) obstacle_detection_.Reset();
  if (watch_.lost()) people_tracking_.Reset();
}

std::vector<double> NavigationExecutive::MeasureStateVariables(const ExecutiveInputs& in,
                                                               const localization::PoseEstimate& estimate,
                                                               bool detecting, double now) const {
  // Seed 000 section 7: the emergency stop is for stationary things; a bumper pressed by a moving
  // obstacle the robot can see (it would wait for the robot forever) is the avoidance behaviour's.
  bool contact = in.contact;
  double danger_level = danger();
  const double rim = moving_.detection.robot_radius;
  if (contact && people_.enabled) {
    // Among people, what presses a bumper is someone who walked into the robot: a tracked person
    // at the pressed side, or, at the rear the laser cannot see, anyone. Stopping there invites
    // the next one; the crowd controller takes the robot away instead.
    if (in.rear_contact_only) contact = false;
    for (const TrackedPerson& p : people_tracking_.People(now)) {
      const double gap = Distance(p.position, estimate.pose.translation()) - people_.person_radius - rim;
      if (gap < moving_.touch_gap) contact = false;
    }
  }
  if (contact && layout_.avoidance >= 0 && detecting) {
    for (const DetectedObstacle& o : obstacle_detection_.confirmed()) {
      const double gap = (o.position - estimate.pose.translation()).norm() - o.radius - rim;
      // Only on the pressed side: the laser cannot see what presses the rear bumper.
      const bool in_front = (estimate.pose.inverse() * o.position).x() > 0.0;
      if (gap < moving_.touch_gap && in_front != in.rear_contact_only) {
        contact = false;
        // Among people the crowd controller gets the robot away from whoever walked into it.
        if (!people_.enabled) danger_level = 1.0;
      }
    }
  }
  std::vector<double> z(brain_.options().state_variables.size(), 0.0);
  if (layout_.z_contact >= 0) z[layout_.z_contact] = contact ? 1.0 : 0.0;
  if (layout_.z_stale >= 0) z[layout_.z_stale] = in.sensors_fresh && estimate.valid ? 0.0 : 1.0;
  if (layout_.z_lost >= 0) z[layout_.z_lost] = watch_.lost() ? 1.0 : 0.0;
  // Among people the crowd controller does the avoiding.
  if (layout_.z_danger >= 0) z[layout_.z_danger] = people_.enabled ? 0.0 : danger_level;
  if (layout_.z_map_building >= 0) z[layout_.z_map_building] = map_building_ ? 1.0 : 0.0;
  return z;
}

NavigationExecutive::Decision NavigationExecutive::Decide(const ExecutiveInputs& in, double now) {
  const localization::PoseEstimate estimate = localizer_.Estimate();
  if (estimate.valid && in.sensors_fresh) watch_.Watch(estimate, in.odometry, in.scans, now);
  const bool detecting = layout_.detection >= 0 && brain_.active(static_cast<size_t>(layout_.detection));
  Perceive(in, estimate, detecting, now);
  const std::vector<double> z = MeasureStateVariables(in, estimate, detecting, now);
  const double dt = last_step_ < 0.0 || now <= last_step_ ? 0.0 : std::min(now - last_step_, 1.0);
  last_step_ = now;
  brain_.Update(dt, z);
  if (layout_.memory >= 0 && brain_.active(static_cast<size_t>(layout_.memory))) memory_process_.Step();
  const size_t motor = brain_.active_motor();
  navigator_.SetBehaviour(brain_.name(motor), brain_.Snapshot());
  {
    std::vector<planning::MovingBody> seen;
    for (const DetectedObstacle& o : obstacle_detection_.confirmed())
      seen.push_back({o.position, o.velocity, o.radius, false});
    if (people_.enabled)
      for (const TrackedPerson& p : people_tracking_.People(now))
        seen.push_back({p.position, p.velocity, people_.person_radius, true});
    navigator_.SetMovingObstacles(obstacle_detection_.danger(), std::move(seen));
  }

  if (layout_.wake_up >= 0)
    watch_.Search(estimate, in.odometry, brain_.active(static_cast<size_t>(layout_.wake_up)), now);

  const bool fresh = in.sensors_fresh && estimate.valid;
  // Another behaviour taking the robot ends a recovery; the leg is replanned when navigation has it back.
  if (motor != layout_.navigation) recovery_.Stop();
  const MotorInputs inputs{estimate.pose,
                           fresh,
                           in.contact,
                           in.rear_contact_only,
                           brain_.activated(motor),
                           in.rear_free,
                           now,
                           [&](double rear_free) { return Sensing(estimate.pose, rear_free); }};
  if (static_cast<long>(motor) == layout_.emergency_stop) {
    if (!fresh) return {navigator_.Step(estimate.pose, now, false)};
    return {*Carry(stop_behaviour_, motor, inputs)};
  }
  stop_behaviour_.Release();
  if (static_cast<long>(motor) == layout_.wake_up) return {*Carry(wake_up_behaviour_, motor, inputs)};
  if (static_cast<long>(motor) == layout_.avoidance) {
    if (const std::optional<WheelSpeeds> w = Carry(avoidance_behaviour_, motor, inputs)) return {*w};
    navigator_.SetBehaviour(brain_.name(layout_.navigation), brain_.Snapshot());  // the one that drives
  }
  avoidance_behaviour_.Release();
  return Navigation(in, estimate.pose, fresh, detecting, now);
}

NavigationExecutive::Decision NavigationExecutive::Navigation(const ExecutiveInputs& in, const Pose2& pose, bool fresh,
                                                              bool detecting, double now) {
  if (const std::optional<WheelSpeeds> w = Recover(pose, in.rear_free, fresh, now)) return {*w};
  if (const std::optional<WheelSpeeds> w = legs_.DriveBackOntoGrid(pose, fresh, now))
    return {*w, CommandSource::kGridReentry, detecting};
  if (now - last_blocked_check_ >= moving_.replan_period) {
    last_blocked_check_ = now;
    legs_.ReplanIfBlocked(pose, people_.enabled);
  }
  legs_.PlanLeg(pose, now);
  const std::optional<WheelSpeeds> among_people =
      people_.enabled && fresh ? crowd_.Steer(
                                     navigator_, planning_, pose, last_wheels_, [this] { return people(); }, now)
                               : std::nullopt;
  WheelSpeeds wheels = navigator_.Step(pose, now, fresh);
  legs_.PlanLeg(pose, now);  // a leg that ended this step gets its path now, not a control period later
  if (among_people && navigator_.Status().feedback.state == NavigationState::kDriving) {
    wheels = *among_people;
  } else if (fresh) {
    wheels = Reflex(wheels, in, pose);
  }
  return {wheels, CommandSource::kNavigation, detecting};
}

std::optional<WheelSpeeds> NavigationExecutive::Recover(const Pose2& pose, double rear_free, bool fresh, double now) {
  if (navigator_.TakeStuck()) {
    const RecoveryKind kind = NthRecovery(navigator_.Status().feedback.recoveries);
    if (kind == RecoveryKind::kClear) {
      obstacle_detection_.Reset();
      sensed_.ForgetAll();
    }
    recovery_.Start(kind, pose, now);
  }
  if (!recovery_.active()) return std::nullopt;
  const std::optional<WheelSpeeds> w =
      fresh ? recovery_.Step(pose, Sensing(pose, rear_free).rear_free, now) : WheelSpeeds{};
  if (w) {
    navigator_.Hold(pose, now, NavigationState::kRecovering,
                    std::string("stuck: recovery '") + RecoveryKindName(recovery_.kind()) + "' (" +
                        std::to_string(navigator_.Status().feedback.recoveries) + " so far)",
                    fresh);
  }
  return w;
}

std::vector<Point2> NavigationExecutive::MovingRims(const Pose2& pose) const {
  std::vector<Point2> local;
  for (const DetectedObstacle& o : obstacle_detection_.candidates()) {
    // Standing things are the plans' business: they go round them, closer than a guard would let.
    if (o.velocity.norm() >= moving_.guard_min_speed) AddPredictedRim(o, pose, {0.0, 0.5, 1.0}, local);
  }
  return local;
}

}  // namespace navd::navigation
