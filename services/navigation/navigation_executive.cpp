#include "services/navigation/navigation_executive.h"

#include <cmath>

#include "services/common/error.h"

namespace navd::navigation {

namespace {
const char* const kMeasured[] = {"contact", "sensors_stale", "localization_lost"};

long StateIndexOr(const UtilityDecisionMaker& brain, const char* name) {
  const auto& vars = brain.options().state_variables;
  for (size_t k = 0; k < vars.size(); ++k)
    if (vars[k] == name) return static_cast<long>(k);
  return -1;
}
}  // namespace

NavigationExecutive::NavigationExecutive(planning::PlanningEngine& planning, localization::Localizer& localizer,
                                         const Clock& clock, const NavigatorOptions& options,
                                         const UtilityBrainOptions& brain, const LocalizationWatchOptions& watch)
    : planning_(planning), localizer_(localizer), clock_(clock), navigator_(options), brain_(brain), watch_(watch) {
  for (const std::string& v : brain_.options().state_variables) {
    bool known = false;
    for (const char* m : kMeasured) known = known || v == m;
    if (!known) {
      throw Error(ErrorCode::kInvalidArgument,
                  "brain: state variable '" + v + "' is not one navd measures (contact, sensors_stale, "
                  "localization_lost)");
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
  for (const auto& [name, index] : {std::pair<const char*, long>{"emergency_stop", emergency_stop_},
                                    {"wake_up", wake_up_}}) {
    if (index >= 0 && brain_.options().processes[index].kind != ProcessKind::kMotor) {
      throw Error(ErrorCode::kInvalidArgument, std::string("brain: '") + name + "' must be a motor behaviour");
    }
  }
  if (localization_ >= 0 && brain_.options().processes[localization_].kind != ProcessKind::kCognitive) {
    throw Error(ErrorCode::kInvalidArgument, "brain: 'localization' must be a cognitive process");
  }
  for (const auto& p : brain_.options().processes) {
    if (p.name != "navigation" && p.name != "emergency_stop" && p.name != "wake_up" && p.name != "localization") {
      throw Error(ErrorCode::kInvalidArgument, "brain: process '" + p.name +
                                                   "' is not one navd runs (navigation, emergency_stop, "
                                                   "wake_up, localization)");
    }
  }
  z_contact_ = StateIndexOr(brain_, "contact");
  z_stale_ = StateIndexOr(brain_, "sensors_stale");
  z_lost_ = StateIndexOr(brain_, "localization_lost");
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

uint64_t NavigationExecutive::StartMission(const Mission& mission, const std::string& planner, bool preempt,
                                           const planning::StopRequested& stop) {
  const localization::PoseEstimate estimate = localizer_.Estimate();
  if (!estimate.valid) {
    throw Error(ErrorCode::kFailedPrecondition, "no pose estimate yet: navd has not received odometry");
  }
  planning::PathPlan first;
  if (mission.waypoints.size() == 1) {
    // Validates the goal (finite, inside the map, free) and fails early when no path exists.
    first = planning_.ComputePath(estimate.pose.translation(), mission.waypoints[0].pose.translation(), planner, {},
                                  stop);
  } else {
    // Every waypoint and every leg is checked now, not when the robot gets there; errors name
    // waypoints[i]. A cyclic mission's closing leg is checked as well.
    std::vector<Point2> points;
    for (const auto& w : mission.waypoints) points.push_back(w.pose.translation());
    if (mission.cyclic) points.push_back(points.front());
    planning_.ComputePathThroughPoses(estimate.pose.translation(), points, planner, {}, stop);
    first = planning_.ComputePath(estimate.pose.translation(), points.front(), planner, {}, stop);
  }
  const uint64_t id = navigator_.Start(mission, first.points, first.length, clock_.Now(), preempt);
  planner_ = planner;
  return id;
}

void NavigationExecutive::PlanLeg(double now) {
  const std::optional<NavigationGoal> leg = navigator_.LegToPlan();
  if (!leg) return;
  const localization::PoseEstimate estimate = localizer_.Estimate();
  try {
    const planning::PathPlan plan =
        planning_.ComputePath(estimate.pose.translation(), leg->pose.translation(), planner_, {});
    navigator_.SetLegPath(plan.points, plan.length, now);
  } catch (const Error& e) {
    navigator_.Abort("no path to waypoint " + FormatPoint(leg->pose.translation()) + ": " + e.what(), now);
  }
}

void NavigationExecutive::WatchLocalization(const localization::PoseEstimate& e, uint64_t scans, double now) {
  const double spread = std::sqrt(std::max(0.0, e.covariance(0, 0) + e.covariance(1, 1)));
  const bool new_scan = scans != last_scans_;
  last_scans_ = scans;
  if (lost_) {
    if (e.quality >= watch_.found_quality && spread <= watch_.max_spread) lost_ = false;
    poor_fit_since_ = -1.0;
    poor_scans_ = 0;
    return;
  }
  if (e.quality < watch_.lost_quality) {
    if (poor_fit_since_ < 0.0) poor_fit_since_ = now;
    if (new_scan) ++poor_scans_;
    const bool enough_scans = scans == 0 || poor_scans_ >= watch_.lost_scans;
    if (now - poor_fit_since_ >= watch_.lost_after && enough_scans) lost_ = true;
  } else {
    poor_fit_since_ = -1.0;
    poor_scans_ = 0;
  }
}

WheelSpeeds NavigationExecutive::Step(const ExecutiveInputs& in, double now) {
  const localization::PoseEstimate estimate = localizer_.Estimate();
  if (estimate.valid && in.sensors_fresh) WatchLocalization(estimate, in.scans, now);

  std::vector<double> z(brain_.options().state_variables.size(), 0.0);
  if (z_contact_ >= 0) z[z_contact_] = in.contact ? 1.0 : 0.0;
  if (z_stale_ >= 0) z[z_stale_] = in.sensors_fresh && estimate.valid ? 0.0 : 1.0;
  if (z_lost_ >= 0) z[z_lost_] = lost_ ? 1.0 : 0.0;
  const double dt = last_step_ < 0.0 || now <= last_step_ ? 0.0 : std::min(now - last_step_, 1.0);
  last_step_ = now;
  brain_.Update(dt, z);
  const size_t motor = brain_.active_motor();
  navigator_.SetBehaviour(brain_.name(motor), brain_.Snapshot());

  if (wake_up_ >= 0 && brain_.activated(static_cast<size_t>(wake_up_))) localizer_.GlobalRelocalize();

  const bool fresh = in.sensors_fresh && estimate.valid;
  if (static_cast<long>(motor) == emergency_stop_) {
    if (!fresh) return navigator_.Step(estimate.pose, now, false);
    navigator_.Hold(estimate.pose, now, NavigationState::kEmergencyStop, in.contact ? "bumper pressed" : "emergency stop",
                    fresh);
    return {};
  }
  if (static_cast<long>(motor) == wake_up_) {
    navigator_.Hold(estimate.pose, now, NavigationState::kEmergencyStop, "localization lost: searching the map", fresh);
    // Turning in place shows the filter the whole room; it cannot tell places apart standing still.
    const double v = watch_.search_turn_rate * navigator_.options().follower.wheel_base / 2.0;
    return {-v, v};
  }
  PlanLeg(now);
  const WheelSpeeds wheels = navigator_.Step(estimate.pose, now, fresh);
  PlanLeg(now);  // a leg that ended this step gets its path now, not a control period later
  return wheels;
}

}  // namespace navd::navigation
