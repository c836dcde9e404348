// The executive's parts without transport: utility-function decision making (seed 000 section 3),
// the brain file, waypoint missions in the navigator, and the executive's emergency stop.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <set>
#include <thread>
#include <vector>

#include "services/common/diff_drive.h"
#include "services/common/error.h"
#include "services/common/map_store.h"
#include "services/common/ray_caster.h"
#include "services/localization/odometry_localizer.h"
#include "services/localization/particle_filter.h"
#include "services/navigation/navigation_executive.h"
#include "services/navigation/navigator.h"
#include "services/planning/planner_catalog.h"
#include "services/navigation/utility_decision_maker.h"

namespace navd::navigation {
namespace {

UtilityBrainOptions TwoBehaviours() {
  UtilityBrainOptions o;
  o.state_variables = {"danger"};
  o.processes = {{"navigation", ProcessKind::kMotor, 0.1, 1.0, 0.25, {}},
                 {"avoid", ProcessKind::kMotor, 0.1, 1.0, -0.45, {{"danger", 1.0}}},
                 {"watch", ProcessKind::kCognitive, 0.1, 1.0, -0.2, {{"danger", 1.0}}}};
  return o;
}

TEST(UtilityDecisionMaker, UtilitiesFollowTheFirstOrderLawExactly) {
  UtilityDecisionMaker brain(TwoBehaviours());
  // u(t) = tanh(b) (1 - exp(-t / tau)) from u(0) = 0 with z held at 0.
  for (int i = 0; i < 10; ++i) brain.Update(0.01, {0.0});
  EXPECT_NEAR(brain.utility(0), std::tanh(0.25) * (1 - std::exp(-1.0)), 1e-12);
  EXPECT_NEAR(brain.utility(1), std::tanh(-0.45) * (1 - std::exp(-1.0)), 1e-12);
  // The step size does not matter for held inputs: one step of 0.1 s lands on the same value.
  UtilityDecisionMaker coarse(TwoBehaviours());
  coarse.Update(0.1, {0.0});
  EXPECT_NEAR(coarse.utility(0), brain.utility(0), 1e-12);
}

TEST(UtilityDecisionMaker, ExactlyOneMotorBehaviourAndEveryPositiveCognitiveProcess) {
  UtilityDecisionMaker brain(TwoBehaviours());
  for (int i = 0; i < 100; ++i) brain.Update(0.02, {0.0});
  EXPECT_EQ(brain.name(brain.active_motor()), "navigation");
  EXPECT_TRUE(brain.active(0));
  EXPECT_FALSE(brain.active(1));
  EXPECT_FALSE(brain.active(2));  // tanh(-0.2) < 0
  // Danger 1: avoidance's target tanh(0.55) = 0.50 beats navigation's 0.245; the watcher turns on.
  for (int i = 0; i < 100; ++i) brain.Update(0.02, {1.0});
  EXPECT_EQ(brain.name(brain.active_motor()), "avoid");
  EXPECT_FALSE(brain.active(0));
  EXPECT_TRUE(brain.active(2));
  int motors = 0;
  for (size_t i = 0; i < 2; ++i) motors += brain.active(i) ? 1 : 0;
  EXPECT_EQ(motors, 1);
}

TEST(UtilityDecisionMaker, GammaSetOnActivationHoldsTheBehaviourThenDecays) {
  UtilityBrainOptions o = TwoBehaviours();
  o.processes[1].gamma_on_activation = 3.0;  // seed 000: Gamma_5 = 3 in avoidance's state 1
  o.processes[1].gamma_tau = 1.0;
  UtilityDecisionMaker brain(o);
  for (int i = 0; i < 50; ++i) brain.Update(0.02, {0.0});
  // A moment of danger activates avoidance, which sets its gamma...
  double t = 0.0;
  while (brain.active_motor() != 1u && t < 1.0) {
    brain.Update(0.02, {1.0});
    t += 0.02;
  }
  ASSERT_EQ(brain.active_motor(), 1u);
  EXPECT_DOUBLE_EQ(brain.Snapshot()[1].gamma, 3.0);
  // ... which keeps it in control after the danger is gone, until 3 e^{-t} - 0.45 < 0.25, i.e.
  // about 1.46 s after activation with tau_Gamma = 1 s (plus the utilities' 0.1 s lag).
  t = 0.0;
  while (brain.active_motor() == 1u && t < 10.0) {
    brain.Update(0.02, {0.0});
    t += 0.02;
  }
  EXPECT_GT(t, 1.2);
  EXPECT_LT(t, 1.9);
  EXPECT_EQ(brain.name(brain.active_motor()), "navigation");
  // A process can end itself at once with a large negative gamma.
  for (int i = 0; i < 50; ++i) brain.Update(0.02, {1.0});
  ASSERT_EQ(brain.active_motor(), 1u);
  brain.SetGamma(1, -10.0);
  for (int i = 0; i < 10; ++i) brain.Update(0.02, {1.0});
  EXPECT_EQ(brain.active_motor(), 0u);
}

TEST(UtilityDecisionMaker, RejectsBrainsThatCannotWork) {
  UtilityBrainOptions none = TwoBehaviours();
  none.processes = {{"watch", ProcessKind::kCognitive, 0.1, 1.0, 0.5, {}}};
  EXPECT_THROW(UtilityDecisionMaker{none}, Error);
  UtilityBrainOptions twice = TwoBehaviours();
  twice.processes.push_back(twice.processes[0]);
  EXPECT_THROW(UtilityDecisionMaker{twice}, Error);
  UtilityBrainOptions unknown = TwoBehaviours();
  unknown.processes[1].a = {{"dangr", 1.0}};
  try {
    UtilityDecisionMaker brain(unknown);
    FAIL() << "accepted a weight on an unknown state variable";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("dangr"), std::string::npos) << e.what();
  }
  UtilityBrainOptions slow = TwoBehaviours();
  slow.processes[0].tau = 0.0;
  EXPECT_THROW(UtilityDecisionMaker{slow}, Error);
}

TEST(BrainFile, ShippedFileIsTheBuiltInDefault) {
  const UtilityBrainOptions file = LoadBrainFile(std::string(NAVD_SOURCE_DIR) + "/config/brain.yaml");
  const UtilityBrainOptions builtin = DefaultBrainOptions();
  ASSERT_EQ(file.state_variables, builtin.state_variables);
  ASSERT_EQ(file.processes.size(), builtin.processes.size());
  for (size_t i = 0; i < file.processes.size(); ++i) {
    const auto &a = file.processes[i], &b = builtin.processes[i];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.kind, b.kind) << a.name;
    EXPECT_DOUBLE_EQ(a.tau, b.tau) << a.name;
    EXPECT_DOUBLE_EQ(a.c, b.c) << a.name;
    EXPECT_DOUBLE_EQ(a.b, b.b) << a.name;
    EXPECT_EQ(a.a, b.a) << a.name;
    EXPECT_DOUBLE_EQ(a.gamma_tau, b.gamma_tau) << a.name;
    EXPECT_DOUBLE_EQ(a.gamma_on_activation, b.gamma_on_activation) << a.name;
  }
}

TEST(BrainFile, ErrorsNameTheFileLineAndField) {
  const auto message = [](const std::string& text) {
    try {
      ParseBrain(text, "b.yaml");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_NE(message("state_variables: [a]\nprocesses:\n  - {name: n, kind: motr}\n").find("processes[0].kind"),
            std::string::npos);
  EXPECT_NE(message("state_variables: [a]\nprocesses:\n  - {name: n, kind: motor, tau: -1}\n").find("b.yaml:3"),
            std::string::npos);
  EXPECT_NE(message("state_variables: [a]\nprocesses:\n  - {name: n, kind: motor, a: {b: 1}}\n").find("a.b"),
            std::string::npos);
  EXPECT_NE(message("state_variables: [a]\nprocesses:\n  - {name: n, kind: cognitive}\n").find("motor"),
            std::string::npos);
  EXPECT_NE(message("state_variables: [a]\nprocesses: []\nextra: 1\n").find("extra"), std::string::npos);
  // A missing list is refused by name, not by yaml-cpp's "invalid node" escaping.
  EXPECT_NE(message("processes: []\n").find("'state_variables' must be a list"), std::string::npos);
  EXPECT_NE(message("state_variables: [a]\n").find("'processes' must be a list"), std::string::npos);
}

// Drives a navigator's mission on exact kinematics; returns the number of control steps.
int Drive(Navigator& nav, Pose2& pose, double& t, int max_steps, const std::function<void()>& between = {}) {
  const double dt = 0.05;
  int steps = 0;
  for (; steps < max_steps && nav.Status().active; ++steps) {
    if (auto leg = nav.LegToPlan()) nav.SetLegPath({pose.translation(), leg->pose.translation()}, 0.0, t);
    const WheelSpeeds w = nav.Step(pose, t, true);
    pose = IntegrateDiffDrive(pose, w.left * dt, w.right * dt, nav.options().follower.wheel_base);
    t += dt;
    if (between) between();
  }
  return steps;
}

TEST(NavigatorMission, VisitsWaypointsInOrderForTheRequestedLaps) {
  Navigator nav;
  Pose2 pose{0, 0, 0};
  double t = 0.0;
  nav.Step(pose, t, true);
  Mission m;
  m.waypoints = {{{2, 0, 0}}, {{2, 2, 0}}, {{0, 2, 0}}};
  m.cyclic = true;
  m.laps = 2;
  const uint64_t id = nav.Start(m, {{0, 0}, {2, 0}}, 2.0, t, false);
  std::vector<uint32_t> order;
  Drive(nav, pose, t, 20000, [&] {
    const uint32_t i = nav.Status().feedback.mission_index;
    if (order.empty() || order.back() != i) order.push_back(i);
  });
  const auto r = nav.ResultOf(id);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->outcome, Outcome::kSucceeded) << r->message;
  EXPECT_EQ(r->waypoints_reached, 6u);
  EXPECT_EQ(order, (std::vector<uint32_t>{0, 1, 2, 0, 1, 2}));
  // 2 + 2 + 2 the first lap; 2.83 back to the first waypoint and 2 + 2 the second; less the
  // corners cut.
  EXPECT_GT(r->distance_travelled, 12.0);
  EXPECT_LT(r->distance_travelled, 12.9);
  EXPECT_LT(Distance(pose.translation(), {0, 2}), 0.06);
}

TEST(NavigatorMission, EndsAfterMaxDistanceAndReportsAFallingEta) {
  Navigator nav;
  Pose2 pose{0, 0, 0};
  double t = 0.0;
  nav.Step(pose, t, true);
  Mission m;
  m.waypoints = {{{3, 0, 0}}, {{0, 0, 0}}};
  m.cyclic = true;  // endless: only the distance ends it
  m.max_distance = 10.0;
  const uint64_t id = nav.Start(m, {{0, 0}, {3, 0}}, 3.0, t, false);
  std::vector<double> etas;
  Drive(nav, pose, t, 20000, [&] {
    const auto s = nav.Status();
    if (s.active) etas.push_back(s.feedback.eta);
  });
  const auto r = nav.ResultOf(id);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->outcome, Outcome::kSucceeded);
  EXPECT_NE(r->message.find("max_distance"), std::string::npos) << r->message;
  EXPECT_GE(r->distance_travelled, 10.0);
  EXPECT_LT(r->distance_travelled, 10.2);
  // With an endless mission and a distance limit, the ETA is the distance left at the mission's pace.
  ASSERT_GT(etas.size(), 100u);
  EXPECT_GT(etas[etas.size() / 4], etas[3 * etas.size() / 4]);
  EXPECT_LT(etas.back(), 1.0);
}

TEST(NavigatorMission, PauseStopsTheRobotAndResumeReplans) {
  Navigator nav;
  Pose2 pose{0, 0, 0};
  double t = 0.0;
  nav.Step(pose, t, true);
  EXPECT_THROW(nav.Pause(t), Error);  // nothing to pause
  const uint64_t id = nav.Start(NavigationGoal{{4, 0, 0}}, {{0, 0}, {4, 0}}, 4.0, t, false);
  for (int i = 0; i < 40; ++i) {
    const WheelSpeeds w = nav.Step(pose, t, true);
    pose = IntegrateDiffDrive(pose, w.left * 0.05, w.right * 0.05, 0.33);
    t += 0.05;
  }
  nav.Pause(t);
  EXPECT_THROW(nav.Pause(t), Error);  // already paused
  for (int i = 0; i < 2000; ++i) {    // 100 s paused: longer than the progress timeout, and no failure
    const WheelSpeeds w = nav.Step(pose, t, true);
    EXPECT_EQ(w.left, 0.0);
    EXPECT_EQ(w.right, 0.0);
    t += 0.05;
  }
  EXPECT_TRUE(nav.Status().active);
  EXPECT_EQ(nav.Status().feedback.state, NavigationState::kPaused);
  pose = {1.5, 0.5, 0.3};  // pushed aside while paused
  nav.Resume(t);
  EXPECT_THROW(nav.Resume(t), Error);
  ASSERT_TRUE(nav.LegToPlan());  // replans from where the robot is now
  Drive(nav, pose, t, 4000);
  EXPECT_EQ(nav.ResultOf(id)->outcome, Outcome::kSucceeded);
  EXPECT_LT(Distance(pose.translation(), {4, 0}), 0.06);
}

TEST(NavigatorMission, RejectsAnEmptyMission) {
  Navigator nav;
  EXPECT_THROW(nav.Start(Mission{}, {}, 0.0, 0.0, false), Error);
}

// An executive on a 6 x 5 m open floor (nothing mapped), the robot at (1, 2.5) facing +x, driven
// by odometry alone.
struct OpenFloor {
  explicit OpenFloor(const NavigatorOptions& o = {}, const UtilityBrainOptions& b = DefaultBrainOptions())
      : options(o), brain(b) {
    maps.Set(OccupancyGrid(120, 100, 0.05, Point2(0.0, 0.0)), "open");
    planning::RegisterDefaultPlanners(planning);
  }
  NavigatorOptions options;
  UtilityBrainOptions brain;
  MapStore maps;
  planning::PlanningEngine planning{maps, {}};
  localization::OdometryLocalizer localizer{Pose2(1.0, 2.5, 0.0)};
  SimClock clock;
  NavigationExecutive executive{planning, localizer, clock, options, brain};
};

// People from a detector (navd --people-source topic) on a robot without a laser: a report in the
// robot's frame lands in the map where the estimate puts the robot, through the odometry of the
// report's stamp (the odometry frame is not the map frame here), and is predicted on from when it
// was seen by the robot's clock.
TEST(NavigationExecutive, PeopleReportedByADetectorLandWhereTheEstimatePutsTheRobot) {
  MapStore maps;
  maps.Set(OccupancyGrid(120, 100, 0.05, Point2(0.0, 0.0)), "open");
  planning::PlanningEngine planning{maps, {}};
  planning::RegisterDefaultPlanners(planning);
  localization::OdometryLocalizer localizer{Pose2(1.0, 2.5, M_PI / 2)};
  SimClock clock;
  PeopleAwareOptions people;
  people.enabled = true;
  people.source = PeopleAwareOptions::Source::kReports;
  NavigationExecutive executive{planning, localizer, clock, NavigatorOptions{}, DefaultBrainOptions(), {}, {}, people};
  const Pose2 odometry(5.0, 5.0, 0.0);
  clock.Set(1.0);
  localizer.AddOdometry({odometry, Eigen::Matrix3d::Zero(), 1.0});
  executive.Step(ExecutiveInputs{}, 1.0);
  EXPECT_TRUE(executive.people().empty());
  PeopleReport report;
  report.stamp = 0.9;
  report.people = {{"ann", {2.0, 0.0}, {1.0, 0.0}}};  // 2 m ahead, walking ahead at 1 m/s
  ExecutiveInputs in;
  in.people = &report;
  in.people_odometry = odometry;
  in.odometry = odometry;
  in.people_age = 0.1;
  clock.Set(1.05);
  executive.Step(in, 1.05);
  const std::vector<TrackedPerson> seen = executive.people();
  ASSERT_EQ(seen.size(), 1u);
  // The robot stands at (1, 2.5) facing +y: ann was at (1, 4.5) at t = 0.95, walking along +y.
  EXPECT_NEAR(seen[0].position.x(), 1.0, 1e-9);
  EXPECT_NEAR(seen[0].position.y(), 4.5 + 0.1, 1e-9);
  EXPECT_NEAR(seen[0].velocity.x(), 0.0, 1e-9);
  EXPECT_NEAR(seen[0].velocity.y(), 1.0, 1e-9);
}

// The open floor's robot drives towards (5, 2.5), its bumper is pressed for half a second and
// lets go. `while_pressed`, given the robot's map pose, may change the map meanwhile.
struct ReleaseRun {
  std::vector<WheelSpeeds> pressed;  // the commands while pressed
  double backed = 0.0;               // m backed away after the release
  int backing_steps = 0;
  double driven_on = 0.0;  // m beyond the pressed point two seconds later
  bool active = false;     // the mission still on
};
ReleaseRun PressTheBumperWhileDriving(OpenFloor& floor, const std::function<void(const Pose2&)>& while_pressed = {}) {
  // Named one by one: lambdas below capture them (clang 14, which clang-tidy runs on, cannot capture
  // structured bindings).
  NavigatorOptions& options = floor.options;
  localization::OdometryLocalizer& localizer = floor.localizer;
  SimClock& clock = floor.clock;
  NavigationExecutive& executive = floor.executive;
  const double wheel_base = options.follower.wheel_base;
  Pose2 pose(0.0, 0.0, 0.0);  // odometry
  double t = 0.0;
  auto step = [&](bool contact) {
    t += 0.05;
    clock.Set(t);
    localizer.AddOdometry({pose, Eigen::Matrix3d::Zero(), t});
    ExecutiveInputs in;
    in.contact = contact;
    const WheelSpeeds w = executive.Step(in, t);
    pose = IntegrateDiffDrive(pose, w.left * 0.05, w.right * 0.05, wheel_base);
    return w;
  };
  step(false);
  executive.Navigate({Pose2(5.0, 2.5, 0.0), false, "", false});
  for (int i = 0; i < 40; ++i) step(false);
  ReleaseRun run;
  for (int i = 0; i < 10; ++i) run.pressed.push_back(step(true));
  if (while_pressed) while_pressed(Pose2(1.0, 2.5, 0.0) * pose);
  const double pressed_at = pose.x;
  for (int i = 0; i < 60 && step(false).left < 0.0; ++i) ++run.backing_steps;
  run.backed = pressed_at - pose.x;
  for (int i = 0; i < 40; ++i) step(false);
  run.driven_on = pose.x - pressed_at;
  run.active = executive.navigator().Status().active;
  EXPECT_GT(pressed_at, 0.3);  // it was driving on when pressed
  return run;
}

// A bumper pressed while driving: the emergency stop holds the robot, and when the bumper lets go
// it backs straight away 10 cm before navigation has the robot again (driving on from against the
// obstacle pressed it again and again).
TEST(NavigationExecutive, BacksAwayFromWhatTheBumperTouchedBeforeNavigatingOn) {
  OpenFloor floor;
  bool stopped = false;
  const ReleaseRun run = PressTheBumperWhileDriving(floor, [&](const Pose2&) {
    stopped = floor.executive.navigator().Status().feedback.state == NavigationState::kEmergencyStop;
  });
  for (size_t i = 2; i < run.pressed.size(); ++i) EXPECT_EQ(run.pressed[i].left, 0.0) << i;
  EXPECT_TRUE(stopped);
  EXPECT_NEAR(run.backed, 0.10, 0.02);
  EXPECT_GE(run.backing_steps, 15);  // 10 cm at 0.1 m/s
  // Then navigation drives on to the goal.
  EXPECT_GT(run.driven_on, 0.1);
  EXPECT_TRUE(run.active);
}

// The laser is blind behind: the way back is what the map leaves free for the robot's whole disc.
// A wall's cells reach half a cell past their centres; a door jamb beside the way back, its cells'
// centres clear of the disc but not their squares, was backed into in seed 000's Run 2.
TEST(NavigationExecutive, AWallBesideTheWayBackKeepsTheRobotFromBackingAlongIt) {
  // gap: metres from the robot's centre line to the wall's edge (its radius is 0.20).
  auto backed_beside_a_wall = [](double gap) {
    OpenFloor floor;
    double actual_gap = 0.0;
    const ReleaseRun run = PressTheBumperWhileDriving(floor, [&](const Pose2& at) {
      OccupancyGrid grid = floor.maps.Get()->grid;
      // From a metre behind to just behind the robot's centre, its edge on a cell boundary.
      const double edge = std::ceil((at.y + gap) / grid.resolution() - 0.5) * grid.resolution();
      actual_gap = edge - at.y;
      grid.FillBox(Point2(at.x - 1.0, edge + 0.01), Point2(at.x - 0.05, edge + 0.09));
      floor.maps.Set(std::move(grid), "jamb");
    });
    EXPECT_NEAR(actual_gap, gap, 0.026);
    return run.backed;
  };
  // 21 cm: the cells' centres lie 23.5 cm off, the squares 21; the rim would scrape the wall.
  EXPECT_LT(backed_beside_a_wall(0.21), 0.01);
  EXPECT_NEAR(backed_beside_a_wall(0.30), 0.10, 0.02);
}

// A robot pushing against something nothing senses (an invisible wall 1 m ahead): stuck, it runs
// Nav2's recoveries in turn (clear, back up, spin, wait), replanning after each, and gives the
// mission up only when they are spent; once the way is free again it goes on to the goal.
struct StuckRun {
  std::set<std::string> recoveries;  // the hold reasons seen
  double backed = 0.0, turned = 0.0;
  std::optional<NavigationResult> result;
  uint32_t recoveries_reported = 0;
};
StuckRun DriveAgainstAWall(int max_recoveries, int free_after_recoveries) {
  NavigatorOptions o;
  o.progress_timeout = 3.0;
  o.max_recoveries = max_recoveries;
  OpenFloor floor(o);
  // Named one by one: lambdas below capture them (clang 14, which clang-tidy runs on, cannot capture
  // structured bindings).
  NavigatorOptions& options = floor.options;
  localization::OdometryLocalizer& localizer = floor.localizer;
  SimClock& clock = floor.clock;
  NavigationExecutive& executive = floor.executive;
  Pose2 pose(0.0, 0.0, 0.0);  // odometry
  double t = 0.0;
  StuckRun run;
  clock.Set(t);
  localizer.AddOdometry({pose, Eigen::Matrix3d::Zero(), t});
  executive.Step(ExecutiveInputs{}, t);
  const uint64_t id = executive.Navigate({Pose2(5.0, 2.5, 0.0), false, "", false});
  for (int i = 0; i < 20000 && executive.navigator().Status().active; ++i) {
    t += 0.05;
    clock.Set(t);
    localizer.AddOdometry({pose, Eigen::Matrix3d::Zero(), t});
    const WheelSpeeds w = executive.Step(ExecutiveInputs{}, t);
    const NavigationStatus s = executive.navigator().Status();
    if (s.feedback.state == NavigationState::kRecovering) {
      run.recoveries.insert(s.hold_reason);
      run.backed += std::max(0.0, -(w.left + w.right) / 2.0) * 0.05;
      run.turned += std::abs(w.right - w.left) / options.follower.wheel_base * 0.05;
    }
    pose = IntegrateDiffDrive(pose, w.left * 0.05, w.right * 0.05, options.follower.wheel_base);
    if (static_cast<int>(s.feedback.recoveries) < free_after_recoveries || free_after_recoveries < 0)
      pose.x = std::min(pose.x, 1.0);  // the wall at map x = 2
    run.recoveries_reported = s.feedback.recoveries;
  }
  run.result = executive.navigator().ResultOf(id);
  return run;
}

TEST(NavigationExecutive, AStuckRobotRunsTheRecoveriesInTurnThenGivesUp) {
  const StuckRun run = DriveAgainstAWall(4, -1);
  ASSERT_TRUE(run.result);
  EXPECT_EQ(run.result->outcome, Outcome::kFailed);
  EXPECT_NE(run.result->message.find("after 4 recoveries on this leg"), std::string::npos) << run.result->message;
  EXPECT_EQ(run.recoveries_reported, 4u);
  const std::vector<std::string> expected = {"stuck: recovery 'clear' (1 so far)",
                                             "stuck: recovery 'back up' (2 so far)",
                                             "stuck: recovery 'spin' (3 so far)", "stuck: recovery 'wait' (4 so far)"};
  for (const std::string& e : expected) EXPECT_TRUE(run.recoveries.count(e)) << e;
  EXPECT_NEAR(run.backed, 0.15, 0.03);
  EXPECT_NEAR(run.turned, 1.57, 0.1);
}

TEST(NavigationExecutive, AStuckRobotGoesOnOnceARecoveryFreedIt) {
  const StuckRun run = DriveAgainstAWall(3, 2);  // the wall is gone after the second recovery
  ASSERT_TRUE(run.result);
  EXPECT_EQ(run.result->outcome, Outcome::kSucceeded) << run.result->message;
  EXPECT_EQ(run.recoveries_reported, 2u);
}

// What a 180-degree laser (4 m) at `pose` sees of a wall the map lacks, across the whole map at
// x = `wall` (map frame; infinity: no wall), at time `t`.
localization::ScanReading ScanOfAWallAcross(double wall, const Pose2& pose, double t) {
  localization::ScanReading scan;
  scan.angle_min = -M_PI / 2;
  scan.angle_increment = M_PI / 180;
  scan.range_max = 4.0;
  scan.stamp = t;
  for (int i = 0; i <= 180; ++i) {
    const double c = std::cos(pose.theta + scan.angle_min + i * scan.angle_increment);
    scan.ranges.push_back(c > 1e-6 ? static_cast<float>(std::min(4.0, (wall - pose.x) / c)) : 4.0f);
  }
  return scan;
}

// The scan guard: a wall the map lacks (at x = 3 m across the whole map) stops the robot short of
// it, whatever the plans say, since the laser sees it.
TEST(NavigationExecutive, StopsShortOfAWallOnlyTheLaserSees) {
  OpenFloor floor;
  // Named one by one: lambdas below capture them (clang 14, which clang-tidy runs on, cannot capture
  // structured bindings).
  NavigatorOptions& options = floor.options;
  localization::OdometryLocalizer& localizer = floor.localizer;
  SimClock& clock = floor.clock;
  NavigationExecutive& executive = floor.executive;
  Pose2 odom(0.0, 0.0, 0.0);
  double t = 0.0, farthest = 0.0;
  constexpr double kWall = 3.0;
  auto step = [&] {
    clock.Set(t);
    localizer.AddOdometry({odom, Eigen::Matrix3d::Zero(), t});
    const localization::ScanReading scan = ScanOfAWallAcross(kWall, localizer.Estimate().pose, t);
    ExecutiveInputs in;
    in.scan = &scan;
    const WheelSpeeds w = executive.Step(in, t);
    odom = IntegrateDiffDrive(odom, w.left * 0.05, w.right * 0.05, options.follower.wheel_base);
    farthest = std::max(farthest, localizer.Estimate().pose.x);
    t += 0.05;
  };
  step();
  executive.Navigate({Pose2(5.0, 2.5, 0.0), false, "", false});
  for (int i = 0; i < 400; ++i) step();
  EXPECT_GT(farthest, kWall - 0.2 - 0.15);  // it drove up to the wall...
  EXPECT_LT(farthest, kWall - 0.2 - 0.02);  // ...and stopped short of touching it
}

// Turning in place next to something at the front rim: the wheels never turn quite in place, and
// the creep along the heading touches it. The robot faces +x with a box the map lacks 2 cm ahead;
// its goal lies to its left. While the box is there it turns only as it backs away, never nearer
// (standing there for good, as it once did, left a robot stuck beside a door jamb); once the box
// is gone, it arrives.
TEST(NavigationExecutive, TurnsWithSomethingAtItsRimAheadOnlyAsItBacksAway) {
  OpenFloor floor;
  // Named one by one: lambdas below capture them (clang 14, which clang-tidy runs on, cannot capture
  // structured bindings).
  NavigatorOptions& options = floor.options;
  localization::OdometryLocalizer& localizer = floor.localizer;
  SimClock& clock = floor.clock;
  NavigationExecutive& executive = floor.executive;
  Pose2 odom(0.0, 0.0, 0.0);
  double t = 0.0;
  bool box = true;
  const double rim = MovingObstacleOptions().detection.robot_radius;
  const double box_x = 1.0 + rim + 0.02;  // the robot starts at (1, 2.5), facing +x
  auto step = [&] {
    clock.Set(t);
    localizer.AddOdometry({odom, Eigen::Matrix3d::Zero(), t});
    const localization::ScanReading scan =
        ScanOfAWallAcross(box ? box_x : std::numeric_limits<double>::infinity(), localizer.Estimate().pose, t);
    ExecutiveInputs in;
    in.scan = &scan;
    const WheelSpeeds w = executive.Step(in, t);
    odom = IntegrateDiffDrive(odom, w.left * 0.05, w.right * 0.05, options.follower.wheel_base);
    t += 0.05;
    return w;
  };
  step();
  executive.Navigate({Pose2(1.0, 4.0, M_PI / 2), false, "", false});
  for (int i = 0; i < 60; ++i) {
    const double gap = box_x - localizer.Estimate().pose.x - rim;
    const WheelSpeeds w = step();
    if (w.left != w.right && gap < MovingObstacleOptions().turn_guard_gap) {
      EXPECT_LT(w.left + w.right, 0.0) << "turned without backing at t = " << t;
    }
    EXPECT_LE(localizer.Estimate().pose.x, 1.0 + 1e-6) << "came nearer the box at t = " << t;
  }
  EXPECT_GT(localizer.Estimate().pose.theta, 0.3) << "never turned towards the goal";
  box = false;
  for (int i = 0; i < 400 && executive.navigator().Status().active; ++i) step();
  EXPECT_FALSE(executive.navigator().Status().active);
  EXPECT_NEAR(localizer.Estimate().pose.y, 4.0, 0.15);
}

// Nav2's bumper layer: a post nothing but the bumper senses, straight across the path. The robot
// bumps it and backs away; the replanned leg leads into it again while the post's disc is too near
// the start to be planned round (the planner leaves such bodies out), until the recoveries' back-up
// takes the robot far enough; then it goes round and arrives (6 contacts). Bounded: a wall it
// cannot get round ends the mission after the recoveries, naming where it bumped.
struct BumpRun {
  int contacts = 0;
  std::optional<NavigationResult> result;
};
BumpRun DriveIntoSomethingOnlyTheBumperFeels(double half_x, double half_y) {
  OpenFloor floor;
  // Named one by one: lambdas below capture them (clang 14, which clang-tidy runs on, cannot capture
  // structured bindings).
  NavigatorOptions& options = floor.options;
  localization::OdometryLocalizer& localizer = floor.localizer;
  SimClock& clock = floor.clock;
  NavigationExecutive& executive = floor.executive;
  const Point2 post(3.0, 2.5);
  Pose2 odom(0.0, 0.0, 0.0);
  const Pose2 offset(1.0, 2.5, 0.0);  // map pose = offset * odom
  double t = 0.0;
  bool pressed = false;
  BumpRun run;
  clock.Set(t);
  localizer.AddOdometry({odom, Eigen::Matrix3d::Zero(), t});
  executive.Step(ExecutiveInputs{}, t);
  const uint64_t id = executive.Navigate({Pose2(5.0, 2.5, 0.0), false, "", false});
  for (int i = 0; i < 12000 && executive.navigator().Status().active; ++i) {
    t += 0.05;
    clock.Set(t);
    localizer.AddOdometry({odom, Eigen::Matrix3d::Zero(), t});
    ExecutiveInputs in;
    in.contact = pressed;
    const WheelSpeeds w = executive.Step(in, t);
    const Pose2 next = IntegrateDiffDrive(odom, w.left * 0.05, w.right * 0.05, options.follower.wheel_base);
    const Point2 at = (offset * next).translation();
    // A box centred on (3, 2.5): a post, or a wall across the floor.
    const Point2 nearest(std::clamp(at.x(), post.x() - half_x, post.x() + half_x),
                         std::clamp(at.y(), post.y() - half_y, post.y() + half_y));
    const bool touches = Distance(at, nearest) < 0.2;
    if (touches && !pressed) ++run.contacts;
    pressed = touches && (w.left + w.right) > 0.0;  // pushing into it keeps the bumper pressed
    if (!touches) odom = next;
  }
  run.result = executive.navigator().ResultOf(id);
  return run;
}

TEST(NavigationExecutive, WhatTheBumperHitGoesIntoThePlansAndRepeatedBumpsAreBounded) {
  const BumpRun post = DriveIntoSomethingOnlyTheBumperFeels(0.1, 0.1);
  ASSERT_TRUE(post.result);
  EXPECT_EQ(post.result->outcome, Outcome::kSucceeded) << post.result->message;
  EXPECT_LE(post.contacts, 8);
  std::printf("post: %d contacts, %s\n", post.contacts, post.result->message.c_str());
  const BumpRun wall = DriveIntoSomethingOnlyTheBumperFeels(0.1, 10.0);
  ASSERT_TRUE(wall.result);
  EXPECT_EQ(wall.result->outcome, Outcome::kFailed);
  EXPECT_NE(wall.result->message.find("bumped into something at"), std::string::npos) << wall.result->message;
  std::printf("wall: %d contacts, %s\n", wall.contacts, wall.result->message.c_str());
}

// A post only the laser sees (the map lacks it), straight across the path: the office run that
// stood 1000 s beside a box. Where the post is too near the robot for the plans to go round it
// (they leave such bodies out), the leg leads into it and the scan guard holds the robot short of
// it; the robot must still get round and arrive.
struct PostRun {
  std::optional<NavigationResult> result;
  double nearest = 1e9;  // metres between the rims, at the closest
  std::set<std::string> reasons;
};
// The laser sees the post only once the robot is within `seen_within` metres of its centre (it
// stood round a corner, say), and from then on.
PostRun DriveTowardsAPostOnlyTheLaserSees(double post_radius, double seen_within) {
  NavigatorOptions o;
  o.progress_timeout = 5.0;
  OpenFloor floor(o);
  // Named one by one: lambdas below capture them (clang 14, which clang-tidy runs on, cannot capture
  // structured bindings).
  NavigatorOptions& options = floor.options;
  localization::OdometryLocalizer& localizer = floor.localizer;
  SimClock& clock = floor.clock;
  NavigationExecutive& executive = floor.executive;
  const Point2 post(3.0, 2.5);
  Pose2 odom(0.0, 0.0, 0.0);
  double t = 0.0;
  PostRun run;
  bool seen = false;
  auto step = [&] {
    clock.Set(t);
    localizer.AddOdometry({odom, Eigen::Matrix3d::Zero(), t});
    const Pose2 pose = localizer.Estimate().pose;
    seen = seen || Distance(pose.translation(), post) < seen_within;
    localization::ScanReading scan;
    scan.angle_min = -M_PI;
    scan.angle_increment = M_PI / 180;
    scan.range_max = 4.0;
    scan.stamp = t;
    for (int i = 0; i < 360; ++i) {
      const double a = pose.theta + scan.angle_min + i * scan.angle_increment;
      const Point2 d(std::cos(a), std::sin(a)), to = post - pose.translation();
      const double along = to.dot(d), off2 = to.squaredNorm() - along * along;
      const double r2 = post_radius * post_radius;
      scan.ranges.push_back(seen && along > 0.0 && off2 < r2 ? static_cast<float>(along - std::sqrt(r2 - off2)) : 4.0f);
    }
    ExecutiveInputs in;
    in.scan = &scan;
    const WheelSpeeds w = executive.Step(in, t);
    const NavigationStatus s = executive.navigator().Status();
    if (!s.hold_reason.empty()) run.reasons.insert(s.hold_reason);
    odom = IntegrateDiffDrive(odom, w.left * 0.05, w.right * 0.05, options.follower.wheel_base);
    run.nearest = std::min(run.nearest, Distance(localizer.Estimate().pose.translation(), post) - post_radius - 0.20);
    t += 0.05;
  };
  step();
  const uint64_t id = executive.Navigate({Pose2(5.0, 2.5, 0.0), false, "", false});
  for (int i = 0; i < 6000 && executive.navigator().Status().active; ++i) step();
  run.result = executive.navigator().ResultOf(id);
  return run;
}

TEST(NavigationExecutive, GetsRoundAPostOnlyTheLaserSeesAcrossThePath) {
  const PostRun run = DriveTowardsAPostOnlyTheLaserSees(0.1, 0.5);
  ASSERT_TRUE(run.result);
  for (const std::string& r : run.reasons) std::printf("held: %s\n", r.c_str());
  EXPECT_EQ(run.result->outcome, Outcome::kSucceeded) << run.result->message;
  EXPECT_GT(run.nearest, 0.0);
  EXPECT_LT(run.result->elapsed, 60.0);  // a recovery or two (5 s without progress each), not a stand
  std::printf("post: %s in %.1f s, nearest %.3f m\n", run.result->message.c_str(), run.result->elapsed, run.nearest);
}

// Seed 000's grid navigation, states 2-5: a robot whose estimate stands where no leg can start
// (here: in a part of the room the map calls unknown, a metre from the mapped floor) is outside
// the navigation grid. The mission is accepted all the same (checked from where the robot will get
// on); the robot, facing away, turns towards the grid, drives straight on once the laser shows the
// way clear, plans the leg from the grid and arrives. Boxed in, it turns in place and gives the
// mission up after give_up_after, saying why.
struct ReentryRun {
  std::optional<NavigationResult> result;
  std::string reason;  // the first hold reason outside the grid
  double turned_before_driving = 0.0, least_x = 1e9;
  bool accepted = false;
};
ReentryRun DriveBackOntoTheGrid(bool boxed_in) {
  NavigatorOptions options;
  options.reentry.give_up_after = 20.0;
  MapStore maps;
  {
    OccupancyGrid grid(120, 100, 0.05, Point2(0.0, 0.0));
    for (int y = 0; y < 100; ++y)
      for (int x = 0; x < 30; ++x) grid.set({x, y}, OccupancyGrid::kUnknown);  // x < 1.5 m: unmapped
    maps.Set(std::move(grid), "half-mapped");
  }
  planning::PlanningEngine planning{maps, {}};
  planning::RegisterDefaultPlanners(planning);
  localization::OdometryLocalizer localizer{Pose2(0.7, 2.5, M_PI)};  // facing away from the mapped floor
  SimClock clock;
  NavigationExecutive executive{planning, localizer, clock, options};
  Pose2 odom(0.0, 0.0, 0.0);
  double t = 0.0;
  ReentryRun run;
  bool driven = false;
  auto step = [&] {
    clock.Set(t);
    localizer.AddOdometry({odom, Eigen::Matrix3d::Zero(), t});
    const Pose2 pose = localizer.Estimate().pose;
    // The laser in the real room, 6 m x 5 m and all free; boxed in, a ring of returns at 0.4 m.
    localization::ScanReading scan;
    scan.angle_min = -M_PI;
    scan.angle_increment = M_PI / 90;
    scan.range_max = 8.0;
    scan.stamp = t;
    for (int i = 0; i < 180; ++i) {
      const double a = pose.theta + scan.angle_min + i * scan.angle_increment;
      const double c = std::cos(a), s = std::sin(a);
      double r = 8.0;
      if (c > 1e-9) r = std::min(r, (6.0 - pose.x) / c);
      if (c < -1e-9) r = std::min(r, -pose.x / c);
      if (s > 1e-9) r = std::min(r, (5.0 - pose.y) / s);
      if (s < -1e-9) r = std::min(r, -pose.y / s);
      scan.ranges.push_back(static_cast<float>(boxed_in ? 0.4 : r));
    }
    ExecutiveInputs in;
    in.scan = &scan;
    const WheelSpeeds w = executive.Step(in, t);
    const NavigationStatus s = executive.navigator().Status();
    if (s.hold_reason.find("outside the navigation grid") != std::string::npos && run.reason.empty())
      run.reason = s.hold_reason;
    const Pose2 before = localizer.Estimate().pose;
    odom = IntegrateDiffDrive(odom, w.left * 0.05, w.right * 0.05, options.follower.wheel_base);
    driven = driven || w.left + w.right > 0.01;
    if (!driven) run.turned_before_driving += std::abs(w.right - w.left) / options.follower.wheel_base * 0.05;
    run.least_x = std::min(run.least_x, before.x);
    t += 0.05;
  };
  step();
  uint64_t id = 0;
  try {
    id = executive.Navigate({Pose2(5.0, 2.5, 0.0), false, "", false});
    run.accepted = true;
  } catch (const Error& e) {
    ADD_FAILURE() << e.what();
    return run;
  }
  for (int i = 0; i < 4000 && executive.navigator().Status().active; ++i) step();
  run.result = executive.navigator().ResultOf(id);
  return run;
}

TEST(NavigationExecutive, OutsideTheGridItTurnsTowardsItDrivesOnWhenClearAndPlansFromThere) {
  const ReentryRun run = DriveBackOntoTheGrid(false);
  ASSERT_TRUE(run.result);
  EXPECT_EQ(run.result->outcome, Outcome::kSucceeded) << run.result->message;
  EXPECT_NE(run.reason.find("start (0.70, 2.50)"), std::string::npos) << run.reason;
  EXPECT_GT(run.turned_before_driving, M_PI - 0.6);  // it turned round before driving...
  EXPECT_GT(run.least_x, 0.6);                       // ...rather than on into the unmapped part
  EXPECT_NEAR(run.result->final_pose.x, 5.0, 0.1);
}

TEST(NavigationExecutive, BoxedInOutsideTheGridItGivesTheMissionUpSayingWhy) {
  const ReentryRun run = DriveBackOntoTheGrid(true);
  ASSERT_TRUE(run.result);
  EXPECT_EQ(run.result->outcome, Outcome::kFailed);
  EXPECT_NE(run.result->message.find("outside the navigation grid for 20 s"), std::string::npos) << run.result->message;
  EXPECT_GT(run.turned_before_driving, 3.0);         // turning in place all along
  EXPECT_NEAR(run.result->final_pose.x, 0.7, 1e-6);  // it never drove: the way was never clear
}

// The brain may pick the avoidance behaviour with nothing ahead to avoid (the danger level lags
// the obstacle that raised it; here a brain that always prefers it, on an empty floor): navigation
// then drives, and the feedback names navigation as the behaviour in control, not the avoidance.
TEST(NavigationExecutive, NamesNavigationWhileItDrivesWithNothingAheadToAvoid) {
  UtilityBrainOptions brain = DefaultBrainOptions();
  for (UtilityProcessOptions& p : brain.processes)
    if (p.name == "moving_obstacle_avoidance") p.b = 0.9;  // above navigation's 0.25 whatever the danger
  OpenFloor floor({}, brain);
  auto& [options, unused_brain, maps, planning, localizer, clock, executive] = floor;
  Pose2 odom;
  double t = 0.0;
  int chosen = 0;
  for (int i = 0; i < 60; ++i, t += 0.05) {
    clock.Set(t);
    localizer.AddOdometry({odom, Eigen::Matrix3d::Zero(), t});
    const WheelSpeeds w = executive.Step(ExecutiveInputs{}, t);
    if (i == 0) executive.Navigate({Pose2(5.0, 2.5, 0.0), false, "", false});
    odom = IntegrateDiffDrive(odom, w.left * 0.05, w.right * 0.05, options.follower.wheel_base);
    const NavigationFeedback f = executive.navigator().Status().feedback;
    for (const ProcessUtility& u : f.utilities) {
      if (u.name != "moving_obstacle_avoidance" || !u.active) continue;
      ++chosen;
      EXPECT_EQ(f.behaviour, "navigation") << "at t = " << t;
    }
  }
  EXPECT_GT(chosen, 50);
  EXPECT_GT(odom.x, 0.3);  // navigation drove
}

// A featureless corridor, 40 m by 3 m (the pedestrian street in small): the robot, localised at
// x = 15 and driving on, has people crowding its laser (four beams in five end on them) for
// `crowded_for` seconds, so the executive declares the pose lost. The wake-up searches around
// where the robot was lost first: once the people have gone, the pose is found where the robot is.
// A global search could never tell x = 15 from any other place along the corridor (street seed 150
// in navd searched the street for ever). Still lost after local_search_for seconds, it searches the
// whole map.
struct CorridorLoss {
  bool lost = false, found = false;
  double error = 0.0;                 // m from the truth when found
  std::vector<std::string> searches;  // the wake-up's messages, in turn
  uint64_t losses = 0;                // the executive's count at the end
};
CorridorLoss LoseThePoseInACorridor(double crowded_for) {
  OccupancyGrid corridor(800, 60, 0.05, Point2(0.0, 0.0));
  corridor.FillBox({0.0, 0.0}, {40.0, 0.1});
  corridor.FillBox({0.0, 2.9}, {40.0, 3.0});
  MapStore maps;
  maps.Set(corridor, "corridor");
  planning::PlanningEngine planning{maps, {}};
  planning::RegisterDefaultPlanners(planning);
  localization::ParticleFilterOptions pf;
  pf.global_particles = 20000;  // the corridor is small
  localization::ParticleFilterLocalizer localizer(corridor, pf);
  localizer.SetPose(Pose2(15.0, 1.5, 0.0), Eigen::Matrix3d::Identity() * 1e-4);
  SimClock clock;
  NavigationExecutive executive{planning, localizer, clock, NavigatorOptions{}};
  const double wheel_base = NavigatorOptions{}.follower.wheel_base;
  Pose2 truth(15.0, 1.5, 0.0);
  const Pose2 odom_origin = truth;
  const RayCaster caster(corridor);
  CorridorLoss out;
  for (int step = 0; step < 500; ++step) {
    const double t = 0.1 * step;
    clock.Set(t);
    const Pose2 odometry = odom_origin.inverse() * truth;
    localizer.AddOdometry({odometry, Eigen::Matrix3d::Zero(), t});
    // Driving on down the corridor (a standing robot's filter skips its scans).
    if (step == 1) executive.Navigate({Pose2(35.0, 1.5, 0.0), false, "", false});
    localization::ScanReading scan;
    scan.angle_min = -M_PI;
    scan.angle_increment = M_PI / 90;
    scan.range_max = 8.0;
    scan.stamp = t;
    const bool crowded = t >= 2.0 && t < 2.0 + crowded_for;
    for (int i = 0; i < 180; ++i) {
      const double r =
          caster.CastOpenEdge(truth.translation(), truth.theta + scan.angle_min + i * scan.angle_increment, 8.0);
      scan.ranges.push_back(static_cast<float>(crowded && i % 5 != 0 ? std::min(r, 0.5 + 0.1 * (i % 6))
                                               : r >= 8.0            ? 9.0
                                                                     : r));
    }
    localizer.AddScan(scan);
    ExecutiveInputs in;
    in.scans = static_cast<uint64_t>(step) + 1;
    in.odometry = odometry;
    const WheelSpeeds w = executive.Step(in, t);
    truth = IntegrateDiffDrive(truth, w.left * 0.1, w.right * 0.1, wheel_base);
    const std::string message = executive.navigator().Status().hold_reason;
    if (executive.searching() && (out.searches.empty() || out.searches.back() != message))
      out.searches.push_back(message);
    out.lost |= executive.localization_lost();
    out.losses = executive.localization_losses();
    if (out.lost && !executive.localization_lost()) {
      out.found = true;
      out.error = Distance(localizer.Estimate().pose.translation(), truth.translation());
      std::printf("crowded %.0f s: found at t=%.1f s, %.2f m from the truth\n", crowded_for, t, out.error);
      return out;
    }
  }
  std::printf("crowded %.0f s: lost %d, not found\n", crowded_for, out.lost);
  return out;
}

TEST(NavigationExecutive, AWakeUpSearchesWhereThePoseWasLostFirst) {
  const CorridorLoss brief = LoseThePoseInACorridor(4.0);
  EXPECT_TRUE(brief.lost);
  EXPECT_TRUE(brief.found);
  EXPECT_EQ(brief.losses, 1u);
  EXPECT_LT(brief.error, 0.3);
  EXPECT_EQ(brief.searches, std::vector<std::string>{"localization lost: searching nearby"});
  // Crowded for good: not found nearby, then the whole map is searched.
  const CorridorLoss lasting = LoseThePoseInACorridor(60.0);
  EXPECT_TRUE(lasting.lost);
  EXPECT_FALSE(lasting.found);
  EXPECT_EQ(lasting.losses, 1u);
  EXPECT_EQ(lasting.searches,
            (std::vector<std::string>{"localization lost: searching nearby", "localization lost: searching the map"}));
}

// Seed 000's long-term memory (section 4.6): the map the localisation process matches scans
// against comes from it. A map served anew (here one with a wall the first lacked, as a map built
// by exploration or loaded over gRPC would be) reaches the particle filter once the process runs,
// not while a map is still being built; then the scans fit again.
TEST(NavigationExecutive, LongTermMemoryHandsANewMapToTheLocalisers) {
  OccupancyGrid first(120, 100, 0.05, Point2(0.0, 0.0));
  first.FillBox({0.0, 0.0}, {6.0, 0.1});
  first.FillBox({0.0, 4.9}, {6.0, 5.0});
  first.FillBox({0.0, 0.0}, {0.1, 5.0});
  first.FillBox({5.9, 0.0}, {6.0, 5.0});
  OccupancyGrid second = first;
  second.FillBox({0.0, 2.5}, {4.5, 2.6});  // a wall 1 m beside the robot's way
  MapStore maps;
  maps.Set(first, "first");
  planning::PlanningEngine planning{maps, {}};
  planning::RegisterDefaultPlanners(planning);
  localization::ParticleFilterLocalizer localizer(first);
  localizer.SetPose(Pose2(1.0, 1.5, 0.0), Eigen::Matrix3d::Identity() * 1e-4);
  SimClock clock;
  NavigationExecutive executive{planning, localizer, clock, NavigatorOptions{}};
  EXPECT_EQ(executive.localizer_map_version(), 1u);
  double t = 0.0;
  auto step = [&](const OccupancyGrid& world) {
    const Pose2 truth(1.0 + 0.5 * t, 1.5, 0.0);  // driving along at 0.5 m/s
    clock.Set(t);
    localizer.AddOdometry({Pose2(0.5 * t, 0.0, 0.0), Eigen::Matrix3d::Zero(), t});
    const RayCaster caster(world);
    localization::ScanReading scan;
    scan.angle_min = -M_PI;
    scan.angle_increment = M_PI / 90;
    scan.range_max = 8.0;
    scan.stamp = t;
    for (int i = 0; i < 180; ++i)
      scan.ranges.push_back(
          static_cast<float>(caster.Cast(truth.translation(), scan.angle_min + i * scan.angle_increment, 8.0)));
    localizer.AddScan(scan);
    executive.Step(ExecutiveInputs{}, t);
    t += 0.1;
    return localizer.Estimate().quality;
  };
  double quality = 0.0;
  for (int i = 0; i < 20; ++i) quality = step(first);
  EXPECT_GT(quality, 0.8) << "the scans fit the first map";
  // The new map is served while it is still being built: the localisers keep the first.
  executive.SetMapBuilding(true);
  maps.Set(second, "second");
  double while_building = 1.0;
  for (int i = 0; i < 15; ++i) while_building = std::min(while_building, step(second));
  EXPECT_EQ(executive.localizer_map_version(), 1u);
  EXPECT_LT(while_building, 0.7) << "the wall the first map lacks should spoil the fit";
  // Built: the long-term memory hands it over.
  executive.SetMapBuilding(false);
  for (int i = 0; i < 200 && executive.localizer_map_version() != 2; ++i) {
    step(second);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(executive.localizer_map_version(), 2u);
  for (int i = 0; i < 10; ++i) quality = step(second);
  EXPECT_GT(quality, 0.8) << "the scans fit the new map once the localiser has it";
  EXPECT_NEAR(localizer.Estimate().pose.y, 1.5, 0.1);
}

}  // namespace
}  // namespace navd::navigation
