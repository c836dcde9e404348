#include "services/navigation/leg_planner.h"

#include <cstdio>

namespace navd::navigation {
namespace {

// Outside the navigation grid: how far to look for the grid (m), and how often to ask whether a
// leg can start from the pose (s; seed 000's state 2, each planning attempt a few milliseconds).
constexpr double kReentrySearch = 3.0;
constexpr double kReentryCheckPeriod = 0.25;
constexpr double kOnTheGrid = 0.05;  // m: the nearest grid point this near is the robot's own cell

}  // namespace

uint64_t LegPlanner::StartMission(const Mission& mission, const std::string& planner, bool preempt, const Pose2& from,
                                  double now, const planning::StopRequested& stop) {
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
    first = check(from.translation());
  } catch (const Error& e) {
    // Seed 000's state 2: a robot outside the navigation grid is not a bad mission. It drives back
    // onto the grid first (GridReentry), so the mission is checked from where it will get on.
    const std::optional<Point2> entry = StartsOffGrid(e) ? NearestGridPoint(from.translation()) : std::nullopt;
    if (!entry) throw;
    check(*entry);
    first = {};  // the first leg is planned once the robot is on the grid
  }
  const uint64_t id = navigator_.Start(mission, first.points, first.length, now, preempt);
  leg_map_version_ = map ? map->version : 0;
  planner_ = planner;
  return id;
}

void LegPlanner::PlanLeg(const Pose2& pose, double now) {
  const std::optional<NavigationGoal> leg = navigator_.LegToPlan();
  if (!leg) return;
  const planning::PlanningScene scene = Scene(pose);
  const auto map = planning_.maps().Get();
  const uint64_t plan_map_version = map ? map->version : 0;
  try {
    planning::PathPlan plan;
    try {
      plan = planning_.ComputePath(pose.translation(), leg->pose.translation(), planner_, {}, {}, scene);
    } catch (const Error&) {
      // The obstacles may close every way for now; they move, so plan on the map alone rather
      // than give the mission up (the avoidance behaviour handles them when they come close).
      if (scene.moving.empty()) throw;
      plan = planning_.ComputePath(pose.translation(), leg->pose.translation(), planner_, {});
    }
    navigator_.SetLegPath(plan.points, plan.length, now);
    leg_map_version_ = plan_map_version;
    reentry_.Stop();
  } catch (const Error& e) {
    // Seed 000's state 2: the leg cannot start where the robot is (it is outside the grid); with
    // its laser it drives back on (states 3-5), and the leg is planned again from there.
    const uint64_t mission = navigator_.Status().goal_id;
    if (reentry_.active() && reentry_mission_ != mission) reentry_.Stop();  // another mission's
    if (StartsOffGrid(e) && !reentry_.TimedOut(now) && NearestGridPoint(pose.translation())) {
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

bool LegPlanner::StartsOffGrid(const Error& e) const {
  // The planning engine's errors about the start begin with the field's name; the laser finds the
  // way back onto the grid, so without a scan there is none.
  if (std::string_view(e.what()).rfind("start ", 0) != 0) return false;
  return sensed_.has_scan_returns();
}

std::optional<Point2> LegPlanner::NearestGridPoint(const Point2& p) const {
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

planning::PlanningScene LegPlanner::Scene(const Pose2& pose) const {
  planning::PlanningScene scene;
  for (const DetectedObstacle& o : detection_.confirmed()) {
    // Seed 000 ignores obstacles beyond Delta: far away they will have moved by the time the
    // robot gets there.
    if ((o.position - pose.translation()).norm() > options_.planning_range) continue;
    scene.moving.push_back({o.position, o.velocity, o.radius, false});
  }
  for (const SensedObstacles::Disc& s : sensed_.discs()) {
    if ((s.position - pose.translation()).norm() <= options_.planning_range)
      scene.moving.push_back({s.position, {0, 0}, s.radius, false});
  }
  if (const auto cells = sensed_.layer_cells()) scene.obstacle_cells = *cells;
  return scene;
}

std::optional<WheelSpeeds> LegPlanner::DriveBackOntoGrid(const Pose2& pose, bool fresh, double now) {
  if (!reentry_.active()) return std::nullopt;
  const std::optional<Point2> toward = NearestGridPoint(pose.translation());
  // State 2, on the grid yet? Asked periodically, and at once when the robot's own cell is on it
  // (rather than turning towards that cell meanwhile).
  const bool own_cell = toward && Distance(*toward, pose.translation()) < kOnTheGrid;
  if (own_cell || now - reentry_checked_at_ >= kReentryCheckPeriod) {
    reentry_checked_at_ = now;
    PlanLeg(pose, now);
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

void LegPlanner::ReplanIfBlocked(const Pose2& pose, bool among_people) {
  // Nav2 replans at 1 Hz; we replan when something has come to lie across the path ahead: a
  // tracked obstacle the map lacks (an unknown box, a cart that stopped), or, after the map
  // changed (a map being built), cells its costmap now calls lethal.
  const double rim = options_.robot_radius;
  std::vector<std::pair<Point2, double>> discs;
  // People come and go across the path all the time: the crowd controller steers round them.
  if (!among_people) {
    for (const DetectedObstacle& o : detection_.confirmed()) discs.emplace_back(o.position, o.radius + rim);
  }
  for (const SensedObstacles::Disc& s : sensed_.discs()) discs.emplace_back(s.position, s.radius + rim);
  if (const auto cells = sensed_.layer_cells()) {
    // Not those the plans leave out either: the cells within the inflation of the leg's goal.
    const std::vector<Point2> leg = navigator_.LegPath();
    const double keep_clear = planning_.inflation_radius() + 0.05;
    for (const Point2& p : *cells) {
      if (Distance(p, pose.translation()) > options_.planning_range) continue;
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
      options_.planning_range);
}

}  // namespace navd::navigation
