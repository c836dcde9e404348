#include "services/navigation/navigation_executive.h"

#include <chrono>
#include <cmath>
#include <initializer_list>
#include <limits>

#include "services/common/error.h"
#include "services/localization/scan_points.h"
#include "services/navigation/free_way.h"
#include "services/navigation/surroundings_sensing.h"
#include "services/navigation/scan_guard.h"
#include "services/navigation/tracked_obstacle_guard.h"

namespace navd::navigation {

namespace {
const char* const kMeasured[] = {"contact", "sensors_stale", "localization_lost", "moving_obstacle_danger",
                                 "map_building"};
const char* const kProcesses[] = {"navigation",
                                  "emergency_stop",
                                  "wake_up",
                                  "localization",
                                  "moving_obstacle_detection",
                                  "moving_obstacle_avoidance",
                                  "long_term_memory"};

// Outside the navigation grid: how far to look for the grid (m), and how often to ask whether a
// leg can start from the pose (s; seed 000's state 2, each planning attempt a few milliseconds).
constexpr double kReentrySearch = 3.0;
constexpr double kReentryCheckPeriod = 0.25;
constexpr double kOnTheGrid = 0.05;  // m: the nearest grid point this near is the robot's own cell

// The utility term process `name` keeps while its manoeuvre runs; 0 without such a process.
double GammaOnActivation(const UtilityDecisionMaker& brain, const char* name) {
  const long k = brain.FindProcess(name);
  return k >= 0 ? brain.options().processes[static_cast<size_t>(k)].gamma_on_activation : 0.0;
}

long StateIndexOr(const UtilityDecisionMaker& brain, const char* name) {
  const auto& vars = brain.options().state_variables;
  for (size_t k = 0; k < vars.size(); ++k)
    if (vars[k] == name) return static_cast<long>(k);
  return -1;
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
      watch_(localizer, watch),
      moving_(moving),
      map_caster_(planning.maps()),
      obstacle_detection_(moving.detection),
      people_(people),
      people_tracking_(people),
      crowd_(people.control),
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
      reentry_(options.reentry) {
  for (const std::string& v : brain_.options().state_variables) {
    bool known = false;
    for (const char* m : kMeasured) known = known || v == m;
    if (!known) {
      throw Error(ErrorCode::kInvalidArgument, "brain: state variable '" + v +
                                                   "' is not one navd measures (contact, sensors_stale, "
                                                   "localization_lost, moving_obstacle_danger, map_building)");
    }
  }
  const long nav = brain_.FindProcess("navigation");
  if (nav < 0 || brain_.options().processes[nav].kind != ProcessKind::kMotor) {
    throw Error(ErrorCode::kInvalidArgument, "brain: a motor behaviour named 'navigation' is required");
  }
  navigation_ = static_cast<size_t>(nav);
  emergency_stop_ = brain_.FindProcess("emergency_stop");
  wake_up_ = brain_.FindProcess("wake_up");
  localization_ = brain_.FindProcess("localization");
  detection_ = brain_.FindProcess("moving_obstacle_detection");
  memory_ = brain_.FindProcess("long_term_memory");
  // The localisers were built on the map served now.
  if (const auto map = planning_.maps().Get()) localizer_map_version_ = map->version;
  avoidance_ = brain_.FindProcess("moving_obstacle_avoidance");
  for (const auto& [name, index] : {std::pair<const char*, long>{"emergency_stop", emergency_stop_},
                                    {"wake_up", wake_up_},
                                    {"moving_obstacle_avoidance", avoidance_}}) {
    if (index >= 0 && brain_.options().processes[index].kind != ProcessKind::kMotor) {
      throw Error(ErrorCode::kInvalidArgument, std::string("brain: '") + name + "' must be a motor behaviour");
    }
  }
  for (const auto& [name, index] : {std::pair<const char*, long>{"localization", localization_},
                                    {"moving_obstacle_detection", detection_},
                                    {"long_term_memory", memory_}}) {
    if (index >= 0 && brain_.options().processes[index].kind != ProcessKind::kCognitive) {
      throw Error(ErrorCode::kInvalidArgument, std::string("brain: '") + name + "' must be a cognitive process");
    }
  }
  for (const auto& p : brain_.options().processes) {
    bool known = false;
    for (const char* k : kProcesses) known = known || p.name == k;
    if (!known) {
      throw Error(ErrorCode::kInvalidArgument, "brain: process '" + p.name +
                                                   "' is not one navd runs (navigation, emergency_stop, wake_up, "
                                                   "localization, moving_obstacle_detection, "
                                                   "moving_obstacle_avoidance, long_term_memory)");
    }
  }
  z_contact_ = StateIndexOr(brain_, "contact");
  z_stale_ = StateIndexOr(brain_, "sensors_stale");
  z_lost_ = StateIndexOr(brain_, "localization_lost");
  z_danger_ = StateIndexOr(brain_, "moving_obstacle_danger");
  z_map_building_ = StateIndexOr(brain_, "map_building");
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
  if (r.use_goal_heading && !std::isfinite(r.goal.theta)) {
    throw Error(ErrorCode::kInvalidArgument, "goal.theta is not a finite number");
  }
  NavigationGoal goal{r.goal, r.use_goal_heading};
  if (!r.use_goal_heading) goal.pose.theta = 0.0;
  return StartMission(Mission{{goal}}, r.planner, r.preempt, stop);
}

uint64_t NavigationExecutive::FollowWaypoints(const MissionRequest& r, const planning::StopRequested& stop) {
  if (r.waypoints.empty()) throw Error(ErrorCode::kInvalidArgument, "waypoints: at least one is required");
  if (r.cyclic && r.waypoints.size() < 2) {
    throw Error(ErrorCode::kInvalidArgument, "waypoints: a cyclic mission needs at least two");
  }
  if (!r.cyclic && r.laps > 0) throw Error(ErrorCode::kInvalidArgument, "laps: only a cyclic mission has laps");
  if (!std::isfinite(r.max_distance) || r.max_distance < 0.0) {
    throw Error(ErrorCode::kInvalidArgument, "max_distance must be a non-negative number of metres");
  }
  Mission mission;
  mission.cyclic = r.cyclic;
  mission.laps = r.laps;
  mission.max_distance = r.max_distance;
  for (size_t i = 0; i < r.waypoints.size(); ++i) {
    if (r.use_goal_heading && !std::isfinite(r.waypoints[i].theta)) {
      throw Error(ErrorCode::kInvalidArgument, "waypoints[" + std::to_string(i) + "].theta is not a finite number");
    }
    NavigationGoal g{r.waypoints[i], r.use_goal_heading};
    if (!r.use_goal_heading) g.pose.theta = 0.0;
    mission.waypoints.push_back(g);
  }
  return StartMission(mission, r.planner, r.preempt, stop);
}

DeliverySchedule NavigationExecutive::PlanDeliveries(const DeliveryRequest& r, const planning::StopRequested& stop) {
  if (r.tasks.empty()) throw Error(ErrorCode::kInvalidArgument, "tasks: at least one is required");
  if (r.tasks.size() > kMaxDeliveryTasks) {
    throw Error(ErrorCode::kInvalidArgument, "tasks: at most " + std::to_string(kMaxDeliveryTasks) + " in one mission");
  }
  const localization::PoseEstimate estimate = localizer_.Estimate();
  if (!estimate.valid) {
    throw Error(ErrorCode::kFailedPrecondition, "no pose estimate yet: navd has not received odometry");
  }
  const Point2 start = estimate.pose.translation();
  // Each stop checked from where the robot is (inside the map, free, reachable): the errors name
  // it. The scheduler asks for these lengths again: they are kept.
  std::vector<std::pair<Point2, double>> from_start;
  for (size_t i = 0; i < r.tasks.size(); ++i) {
    for (const bool pickup : {true, false}) {
      const std::string field = "tasks[" + std::to_string(i) + "]." + (pickup ? "pickup" : "dropoff");
      const Point2& p = pickup ? r.tasks[i].pickup : r.tasks[i].dropoff;
      if (!p.allFinite()) throw Error(ErrorCode::kInvalidArgument, field + " is not a finite point");
      try {
        from_start.emplace_back(p, planning_.ComputePath(start, p, r.planner, {}, stop).length);
      } catch (const Error& e) {
        throw Error(e.code(), field + ": " + e.what());
      }
    }
  }
  return ScheduleDeliveries(start, r.tasks, r.options, [&](const Point2& a, const Point2& b) {
    if (a == start) {
      for (const auto& [p, length] : from_start)
        if (p == b) return length;
    }
    try {
      return planning_.ComputePath(a, b, r.planner, {}, stop).length;
    } catch (const Error&) {
      return std::numeric_limits<double>::infinity();
    }
  });
}

uint64_t NavigationExecutive::Deliver(const DeliveryRequest& r, DeliverySchedule& schedule,
                                      const planning::StopRequested& stop) {
  schedule = PlanDeliveries(r, stop);
  MissionRequest mission;
  for (const DeliveryStop& s : schedule.stops) mission.waypoints.emplace_back(s.at.x(), s.at.y(), 0.0);
  if (r.options.return_to_start) {
    const Point2 start = localizer_.Estimate().pose.translation();
    mission.waypoints.emplace_back(start.x(), start.y(), 0.0);
  }
  mission.planner = r.planner;
  mission.preempt = r.preempt;
  return FollowWaypoints(mission, stop);
}

uint64_t NavigationExecutive::StartMission(const Mission& mission, const std::string& planner, bool preempt,
                                           const planning::StopRequested& stop) {
  const localization::PoseEstimate estimate = localizer_.Estimate();
  if (!estimate.valid) {
    throw Error(ErrorCode::kFailedPrecondition, "no pose estimate yet: navd has not received odometry");
  }
  const auto map = planning_.maps().Get();  // before planning: the plan is at least this new
  planning::PathPlan first;
  std::vector<Point2> points;
  for (const auto& w : mission.waypoints) points.push_back(w.pose.translation());
  // A cyclic mission's closing leg is checked as well.
  if (mission.cyclic && points.size() > 1) points.push_back(points.front());
  auto check = [&](const Point2& from) {
    if (points.size() == 1) {
      // Validates the goal (finite, inside the map, free) and fails early when no path exists.
      return planning_.ComputePath(from, points[0], planner, {}, stop);
    }
    // Every waypoint and every leg is checked now, not when the robot gets there; errors name
    // waypoints[i].
    planning_.ComputePathThroughPoses(from, points, planner, {}, stop);
    return planning_.ComputePath(from, points.front(), planner, {}, stop);
  };
  try {
    first = check(estimate.pose.translation());
  } catch (const Error& e) {
    // Seed 000's state 2: a robot outside the navigation grid is not a bad mission. It drives back
    // onto the grid first (GridReentry), so the mission is checked from where it will get on.
    const std::optional<Point2> entry = StartsOffGrid(e) ? NearestGridPoint(estimate.pose.translation()) : std::nullopt;
    if (!entry) throw;
    check(*entry);
    first = {};  // the first leg is planned once the robot is on the grid
  }
  const uint64_t id = navigator_.Start(mission, first.points, first.length, clock_.Now(), preempt);
  leg_map_version_ = map ? map->version : 0;
  planner_ = planner;
  return id;
}

void NavigationExecutive::PlanLeg(double now) {
  const std::optional<NavigationGoal> leg = navigator_.LegToPlan();
  if (!leg) return;
  const localization::PoseEstimate estimate = localizer_.Estimate();
  const planning::PlanningScene scene = Scene(estimate.pose);
  const auto map = planning_.maps().Get();
  const uint64_t plan_map_version = map ? map->version : 0;
  try {
    planning::PathPlan plan;
    try {
      plan = planning_.ComputePath(estimate.pose.translation(), leg->pose.translation(), planner_, {}, {}, scene);
    } catch (const Error&) {
      // The obstacles may close every way for now; they move, so plan on the map alone rather
      // than give the mission up (the avoidance behaviour handles them when they come close).
      if (scene.moving.empty()) throw;
      plan = planning_.ComputePath(estimate.pose.translation(), leg->pose.translation(), planner_, {});
    }
    navigator_.SetLegPath(plan.points, plan.length, now);
    leg_map_version_ = plan_map_version;
    reentry_.Stop();
  } catch (const Error& e) {
    // Seed 000's state 2: the leg cannot start where the robot is (it is outside the grid); with
    // its laser it drives back on (states 3-5), and the leg is planned again from there.
    const uint64_t mission = navigator_.Status().goal_id;
    if (reentry_.active() && reentry_mission_ != mission) reentry_.Stop();  // another mission's
    if (StartsOffGrid(e) && !reentry_.TimedOut(now) && NearestGridPoint(estimate.pose.translation())) {
      if (!reentry_.active()) {
        reentry_.Start(now);
        reentry_mission_ = mission;
      }
      reentry_why_ = e.what();
      return;
    }
    std::string why = e.what();
    if (reentry_.active()) {
      char buf[64];
      std::snprintf(buf, sizeof buf, " (outside the navigation grid for %.0f s)", now - reentry_.started_at());
      why += buf;
    }
    reentry_.Stop();
    navigator_.Abort("no path to waypoint " + FormatPoint(leg->pose.translation()) + ": " + why, now);
  }
}

void NavigationExecutive::RememberMap() {
  if (map_handover_.valid()) {
    if (map_handover_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
    const uint64_t handed = map_handover_.get();
    if (handed > 0) localizer_map_version_ = handed;  // 0: it failed, and is tried again
  }
  const auto map = planning_.maps().Get();
  if (!map || map->version == localizer_map_version_) return;
  // A localiser's model of a large map (likelihood field, ray caster) takes up to a second to
  // build: not in a control step. The localisers go on with the old map until it is ready.
  try {
    map_handover_ = std::async(std::launch::async, [this, map]() -> uint64_t {
      try {
        localizer_.SetMap(map->grid);
        return map->version;
      } catch (const std::exception&) {
        return 0;  // out of memory, say: the old map stays
      }
    });
  } catch (const std::system_error&) {
    // No thread to be had now; the next step tries again.
  }
}

uint64_t NavigationExecutive::localizer_map_version() const {
  const bool busy =
      map_handover_.valid() && map_handover_.wait_for(std::chrono::seconds(0)) != std::future_status::ready;
  return busy ? 0 : localizer_map_version_.load();
}

bool NavigationExecutive::StartsOffGrid(const Error& e) const {
  // The planning engine's errors about the start begin with the field's name; the laser finds the
  // way back onto the grid, so without a scan there is none.
  if (std::string_view(e.what()).rfind("start ", 0) != 0) return false;
  return sensed_.has_scan_returns();
}

std::optional<Point2> NavigationExecutive::NearestGridPoint(const Point2& p) const {
  const std::shared_ptr<const planning::Costmap> costmap = planning_.CurrentCostmap();
  if (!costmap || !costmap->grid().ContainsPoint(p)) return std::nullopt;
  const CellIndex from = costmap->grid().CellOf(p);
  // Through walls only from inside one (an estimate there is off; the laser finds the way), else
  // the grid point must be reachable from where the robot is.
  const std::optional<CellIndex> cell = costmap->NearestFree(
      from, static_cast<int>(kReentrySearch / costmap->grid().resolution()), costmap->grid().IsOccupied(from));
  if (!cell) return std::nullopt;
  return costmap->grid().CellCenter(*cell);
}

planning::PlanningScene NavigationExecutive::Scene(const Pose2& pose) const {
  planning::PlanningScene scene;
  for (const DetectedObstacle& o : obstacle_detection_.confirmed()) {
    // Seed 000 ignores obstacles beyond Delta: far away they will have moved by the time the
    // robot gets there.
    if ((o.position - pose.translation()).norm() > moving_.planning_range) continue;
    scene.moving.push_back({o.position, o.velocity, o.radius, false});
  }
  for (const SensedObstacles::Disc& s : sensed_.discs()) {
    if ((s.position - pose.translation()).norm() <= moving_.planning_range)
      scene.moving.push_back({s.position, {0, 0}, s.radius, false});
  }
  if (const auto cells = sensed_.layer_cells()) scene.obstacle_cells = *cells;
  return scene;
}

std::vector<TrackedPerson> NavigationExecutive::people() const {
  return people_tracking_.People(people_tracking_.empty() ? 0.0 : clock_.Now());
}

std::optional<WheelSpeeds> NavigationExecutive::SteerAmongPeople(const Pose2& pose, double now) {
  const CrowdControllerOptions& c = people_.control;
  const NavigationStatus status = navigator_.Status();
  const bool steer = status.active && !status.paused && status.feedback.state == NavigationState::kDriving &&
                     status.feedback.distance_remaining > c.handover_distance;
  const double b = navigator_.options().follower.wheel_base;
  const auto hand_back = [&]() -> std::optional<WheelSpeeds> {
    if (crowd_steering_) {
      crowd_steering_ = false;
      navigator_.SetExternalSteering(false);
    }
    return std::nullopt;
  };
  if (!steer) return hand_back();
  std::vector<Point2> path = navigator_.PathAhead(c.lookahead);
  const std::shared_ptr<const planning::Costmap> costmap = planning_.CurrentCostmap();
  // Facing further off than max_heading_error (by default never), the path follower turns the
  // robot round first; the crowd RRT turns it back from anything less.
  const bool facing =
      !path.empty() &&
      std::abs(NormalizeAngle(std::atan2(path.back().y() - pose.y, path.back().x() - pose.x) - pose.theta)) <=
          c.max_heading_error;
  if (!facing || !costmap) return hand_back();
  if (!crowd_steering_) {
    // From what the robot was doing: the path follower's last command.
    crowd_.Reset(std::max(0.0, 0.5 * (last_wheels_.left + last_wheels_.right)),
                 (last_wheels_.right - last_wheels_.left) / b);
    crowd_steering_ = true;
    navigator_.SetExternalSteering(true);
  }
  std::vector<planning::MovingBody> bodies;
  for (const TrackedPerson& p : people()) bodies.push_back({p.position, p.velocity, people_.person_radius, true});
  const UnicycleCommand u = crowd_.Step(*costmap, pose, path, bodies, now);
  return WheelSpeeds{u.v - 0.5 * u.w * b, u.v + 0.5 * u.w * b};
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
  const SonarReflexOptions& o = reflex_.options();
  if (!o.only_unexplained) return echoes;
  const std::vector<Point2> local = sensed_.LocalPoints(pose);
  // A map being built changes every few scans and lacks what it has not seen: the laser alone says.
  const std::shared_ptr<const RayCaster> map = map_building_ ? nullptr : map_caster_.Get();
  const double rim = moving_.detection.robot_radius;
  const double horizon = o.remember_within + o.explained_tolerance;
  std::vector<SonarEcho> out;
  for (const SonarEcho& e : echoes) {
    if (reflex_.GroupOf(e.angle) == SonarGroup::kNone || !(e.range < o.remember_within)) continue;
    const Point2 origin = rim * Point2(std::cos(e.angle), std::sin(e.angle));  // robot frame
    double known = std::numeric_limits<double>::infinity();
    // What the cone would echo from the map and from what the laser sees: the nearest of either
    // within it, widened by kConeSlack for the pose's error. Five rays across the cone missed a door
    // jamb's 10 cm face that the sonar met, and its echoes became obstacles in the doorway.
    constexpr double kConeSlack = 0.05;  // rad
    const double half_cone = o.sensor_cone / 2.0 + kConeSlack;
    if (map) known = NearestInCone(map->grid(), pose * origin, pose.theta + e.angle, half_cone, horizon);
    for (const Point2& p : local) {
      const Point2 d = p - origin;
      if (d.norm() < known && std::abs(NormalizeAngle(std::atan2(d.y(), d.x()) - e.angle)) <= half_cone)
        known = d.norm();
    }
    if (e.range < known - o.explained_tolerance) out.push_back(e);
  }
  return out;
}

double NavigationExecutive::NearestInCone(const OccupancyGrid& grid, const Point2& origin, double heading,
                                          double half_angle, double horizon) {
  double nearest = std::numeric_limits<double>::infinity();
  const CellIndex lo = grid.CellOf(origin - Point2(horizon, horizon)),
                  hi = grid.CellOf(origin + Point2(horizon, horizon));
  for (int y = std::max(lo.y, 0); y <= std::min(hi.y, grid.height() - 1); ++y) {
    for (int x = std::max(lo.x, 0); x <= std::min(hi.x, grid.width() - 1); ++x) {
      const CellIndex c{x, y};
      if (!grid.IsOccupied(c)) continue;
      const double d = grid.DistanceToCell(origin, c);
      if (d >= nearest || d > horizon) continue;
      // A cell is in the cone when any of it is: its centre's bearing, widened by its half-diagonal.
      const Point2 to = grid.CellCenter(c) - origin;
      const double spread = to.norm() > 1e-9 ? std::asin(std::min(1.0, 0.71 * grid.resolution() / to.norm())) : M_PI;
      if (std::abs(NormalizeAngle(std::atan2(to.y(), to.x()) - heading)) <= half_angle + spread) nearest = d;
    }
  }
  return nearest;
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
  if (contact && avoidance_ >= 0 && detecting) {
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
  if (z_contact_ >= 0) z[z_contact_] = contact ? 1.0 : 0.0;
  if (z_stale_ >= 0) z[z_stale_] = in.sensors_fresh && estimate.valid ? 0.0 : 1.0;
  if (z_lost_ >= 0) z[z_lost_] = watch_.lost() ? 1.0 : 0.0;
  // Among people the crowd controller does the avoiding.
  if (z_danger_ >= 0) z[z_danger_] = people_.enabled ? 0.0 : danger_level;
  if (z_map_building_ >= 0) z[z_map_building_] = map_building_ ? 1.0 : 0.0;
  return z;
}

NavigationExecutive::Decision NavigationExecutive::Decide(const ExecutiveInputs& in, double now) {
  const localization::PoseEstimate estimate = localizer_.Estimate();
  if (estimate.valid && in.sensors_fresh) watch_.Watch(estimate, in.odometry, in.scans, now);
  const bool detecting = detection_ >= 0 && brain_.active(static_cast<size_t>(detection_));
  Perceive(in, estimate, detecting, now);
  const std::vector<double> z = MeasureStateVariables(in, estimate, detecting, now);
  const double dt = last_step_ < 0.0 || now <= last_step_ ? 0.0 : std::min(now - last_step_, 1.0);
  last_step_ = now;
  brain_.Update(dt, z);
  if (memory_ >= 0 && brain_.active(static_cast<size_t>(memory_))) RememberMap();
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

  if (wake_up_ >= 0) watch_.Search(estimate, in.odometry, brain_.active(static_cast<size_t>(wake_up_)), now);

  const bool fresh = in.sensors_fresh && estimate.valid;
  // Another behaviour taking the robot ends a recovery; the leg is replanned when navigation has it back.
  if (motor != navigation_) recovery_.Stop();
  const MotorInputs inputs{estimate.pose,
                           fresh,
                           in.contact,
                           in.rear_contact_only,
                           brain_.activated(motor),
                           in.rear_free,
                           now,
                           [&](double rear_free) { return Sensing(estimate.pose, rear_free); }};
  if (static_cast<long>(motor) == emergency_stop_) {
    if (!fresh) return {navigator_.Step(estimate.pose, now, false)};
    return {*Carry(stop_behaviour_, motor, inputs)};
  }
  stop_behaviour_.Release();
  if (static_cast<long>(motor) == wake_up_) return {*Carry(wake_up_behaviour_, motor, inputs)};
  if (static_cast<long>(motor) == avoidance_) {
    if (const std::optional<WheelSpeeds> w = Carry(avoidance_behaviour_, motor, inputs)) return {*w};
    navigator_.SetBehaviour(brain_.name(navigation_), brain_.Snapshot());  // the one that drives
  }
  avoidance_behaviour_.Release();
  return Navigation(in, estimate.pose, fresh, detecting, now);
}

NavigationExecutive::Decision NavigationExecutive::Navigation(const ExecutiveInputs& in, const Pose2& pose, bool fresh,
                                                              bool detecting, double now) {
  if (const std::optional<WheelSpeeds> w = Recover(pose, in.rear_free, fresh, now)) return {*w};
  if (const std::optional<WheelSpeeds> w = DriveBackOntoGrid(pose, fresh, now))
    return {*w, CommandSource::kGridReentry, detecting};
  if (now - last_blocked_check_ >= moving_.replan_period) {
    last_blocked_check_ = now;
    ReplanIfBlocked(pose);
  }
  PlanLeg(now);
  const std::optional<WheelSpeeds> among_people = people_.enabled && fresh ? SteerAmongPeople(pose, now) : std::nullopt;
  WheelSpeeds wheels = navigator_.Step(pose, now, fresh);
  PlanLeg(now);  // a leg that ended this step gets its path now, not a control period later
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

std::optional<WheelSpeeds> NavigationExecutive::DriveBackOntoGrid(const Pose2& pose, bool fresh, double now) {
  if (!reentry_.active()) return std::nullopt;
  const std::optional<Point2> toward = NearestGridPoint(pose.translation());
  // State 2, on the grid yet? Asked periodically, and at once when the robot's own cell is on it
  // (rather than turning towards that cell meanwhile).
  const bool own_cell = toward && Distance(*toward, pose.translation()) < kOnTheGrid;
  if (own_cell || now - reentry_checked_at_ >= kReentryCheckPeriod) {
    reentry_checked_at_ = now;
    PlanLeg(now);
  }
  if (reentry_.active() && navigator_.LegToPlan()) {
    const WheelSpeeds w = fresh ? reentry_.Step(pose, sensed_.LocalPoints(pose), toward, now) : WheelSpeeds{};
    navigator_.Hold(
        pose, now, NavigationState::kRecovering,
        std::string("outside the navigation grid (") + reentry_why_ + "): " + ReentryStateName(reentry_.state()),
        fresh);
    return w;
  }
  reentry_.Stop();  // on the grid, or the mission ended
  return std::nullopt;
}

void NavigationExecutive::ReplanIfBlocked(const Pose2& pose) {
  // Nav2 replans at 1 Hz; we replan when something has come to lie across the path ahead: a
  // tracked obstacle the map lacks (an unknown box, a cart that stopped), or, after the map
  // changed (a map being built), cells its costmap now calls lethal.
  const double rim = moving_.detection.robot_radius;
  std::vector<std::pair<Point2, double>> discs;
  // People come and go across the path all the time: the crowd controller steers round them.
  if (!people_.enabled) {
    for (const DetectedObstacle& o : obstacle_detection_.confirmed()) discs.emplace_back(o.position, o.radius + rim);
  }
  for (const SensedObstacles::Disc& s : sensed_.discs()) discs.emplace_back(s.position, s.radius + rim);
  if (const auto cells = sensed_.layer_cells()) {
    // Not those the plans leave out either: the cells within the inflation of the leg's goal.
    const std::vector<Point2> leg = navigator_.LegPath();
    const double keep_clear = planning_.inflation_radius() + 0.05;
    for (const Point2& p : *cells) {
      if (Distance(p, pose.translation()) > moving_.planning_range) continue;
      if (!leg.empty() && Distance(p, leg.back()) < keep_clear) continue;
      discs.emplace_back(p, rim);
    }
  }
  std::shared_ptr<const planning::Costmap> costmap;
  if (const auto map = planning_.maps().Get(); map && map->version != leg_map_version_)
    costmap = planning_.CurrentCostmap();
  const Point2 here = pose.translation();
  const double near = rim + 0.1;
  navigator_.ReplanIfBlocked(
      [&](const Point2& p) {
        for (const auto& [centre, radius] : discs)
          if (Distance(p, centre) < radius) return true;
        // Not next to the robot: a leg starting inside the inflation leaves it from there.
        if (!costmap || Distance(p, here) < near) return false;
        const CellIndex c = costmap->grid().CellOf(p);
        return costmap->grid().Contains(c) && costmap->IsLethal(c);
      },
      moving_.planning_range);
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
