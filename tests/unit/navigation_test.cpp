// The seed-000 path follower, differential-drive kinematics, and the navigator's goal life cycle.
#include <gtest/gtest.h>

#include <cmath>

#include "services/common/clock.h"
#include "services/common/diff_drive.h"
#include "services/common/error.h"
#include "services/localization/odometry_localizer.h"
#include "services/navigation/grid_reentry.h"
#include "services/navigation/navigator.h"
#include "services/navigation/path_follower.h"
#include "services/navigation/speed_zones.h"
#include "services/common/world.h"

namespace navd::navigation {
namespace {

TEST(DiffDrive, WheelsAndTwistAreInverse) {
  const Twist2 t{0.3, 0.7};
  const WheelSpeeds w = ToWheels(t, 0.33);
  EXPECT_NEAR(w.left, 0.3 - 0.7 * 0.165, 1e-12);
  EXPECT_NEAR(w.right, 0.3 + 0.7 * 0.165, 1e-12);
  const Twist2 back = ToTwist(w, 0.33);
  EXPECT_NEAR(back.v, t.v, 1e-12);
  EXPECT_NEAR(back.omega, t.omega, 1e-12);
}

TEST(DiffDrive, ClampKeepsCurvature) {
  const WheelSpeeds w = ClampWheels({0.2, 1.0}, 0.5);
  EXPECT_NEAR(w.right, 0.5, 1e-12);
  EXPECT_NEAR(w.left, 0.1, 1e-12);
}

TEST(DiffDrive, IntegratesStraightLinesAndArcsExactly) {
  const Pose2 straight = IntegrateDiffDrive({1, 2, M_PI / 2}, 0.5, 0.5, 0.3);
  EXPECT_NEAR(straight.x, 1.0, 1e-12);
  EXPECT_NEAR(straight.y, 2.5, 1e-12);
  // Quarter circle of radius 1 to the left: outer wheel travels (1 + b/2) * pi/2.
  const double b = 0.4, r = 1.0;
  Pose2 p;
  for (int i = 0; i < 100; ++i) p = IntegrateDiffDrive(p, (r - b / 2) * M_PI / 200, (r + b / 2) * M_PI / 200, b);
  EXPECT_NEAR(p.x, 1.0, 1e-9);
  EXPECT_NEAR(p.y, 1.0, 1e-9);
  EXPECT_NEAR(p.theta, M_PI / 2, 1e-9);
  // Turning in place leaves the position alone.
  const Pose2 spin = IntegrateDiffDrive({0, 0, 0}, -0.1, 0.1, b);
  EXPECT_NEAR(spin.x, 0, 1e-12);
  EXPECT_NEAR(spin.theta, 0.2 / b, 1e-12);
}

TEST(PathFollower, RotatesInPlaceWhenHeadingErrorExceedsDelta) {
  PathFollower f;
  f.SetPath({{0, 0}, {0, 2}}, std::nullopt);  // target straight left of a robot facing +x
  const FollowerCommand c = f.Step({0, 0, 0});
  EXPECT_EQ(c.state, FollowerState::kRotating);
  EXPECT_LT(c.wheels.left, 0);
  EXPECT_GT(c.wheels.right, 0);
  EXPECT_NEAR(c.wheels.left, -c.wheels.right, 1e-12);
}

TEST(PathFollower, DrivesWithSeedZeroProportionalLaw) {
  PathFollowerParams p;
  p.v_nav = 0.3;  // below the wheel limit, so the law is not scaled down
  PathFollower f(p);
  f.SetPath({{0, 0}, {2, 0}, {4, 0}}, std::nullopt);
  const double heading = -0.05;  // below delta_resume: drives at once
  const FollowerCommand c = f.Step({0, 0, heading});
  ASSERT_EQ(c.state, FollowerState::kDriving);
  // Target waypoint is (0.5, 0) after densifying; dphi = atan2(0, 0.5) - heading.
  const double dphi = -heading;
  const double dv = p.k_p * p.v_nav * dphi;
  EXPECT_NEAR(c.wheels.left, p.v_nav - dv, 1e-12);
  EXPECT_NEAR(c.wheels.right, p.v_nav + dv, 1e-12);
}

TEST(PathFollower, AdvancesWaypointsWithinDpAndStopsAtTheGoal) {
  PathFollowerParams p;
  p.waypoint_spacing = 0.5;  // d_wp
  p.waypoint_radius = 0.15;  // d_p
  PathFollower f(p);
  f.SetPath({{0, 0}, {1, 0}}, std::nullopt);
  EXPECT_EQ(f.waypoint_count(), 3u);  // densified to d_wp = 0.5
  f.Step({0.40, 0, 0});
  EXPECT_EQ(f.waypoint_index(), 2u);  // 0.1 m from waypoint 1 < d_p
  EXPECT_EQ(f.Step({0.97, 0.0, 0}).state, FollowerState::kArrived);
}

TEST(PathFollower, TurnsToTheRequestedFinalHeading) {
  PathFollower f;
  f.SetPath({{0, 0}, {1, 0}}, M_PI / 2);
  const FollowerCommand c = f.Step({1.0, 0.0, 0.0});
  EXPECT_EQ(c.state, FollowerState::kFinalRotation);
  EXPECT_GT(c.wheels.right, 0);
  EXPECT_EQ(f.Step({1.0, 0.0, M_PI / 2 - 0.01}).state, FollowerState::kArrived);
}

// Closed loop on exact kinematics: the controller brings the robot to the goal of an L-shaped path.
TEST(PathFollower, ClosedLoopReachesTheGoal) {
  PathFollowerParams params;
  PathFollower f(params);
  f.SetPath({{0, 0}, {3, 0}, {3, 2}}, std::nullopt);
  Pose2 pose{0, 0, 2.0};  // starts facing away
  const double dt = 0.05;
  int steps = 0;
  for (; steps < 2000 && f.state() != FollowerState::kArrived; ++steps) {
    const WheelSpeeds w = f.Step(pose).wheels;
    pose = IntegrateDiffDrive(pose, w.left * dt, w.right * dt, params.wheel_base);
  }
  EXPECT_EQ(f.state(), FollowerState::kArrived);
  EXPECT_LT(Distance(pose.translation(), {3, 2}), params.goal_tolerance + 1e-9);
  EXPECT_LT(steps * dt, 40.0);
}

// Seed 000's states 3-5: turn in place while the sector ahead holds an obstacle, drive straight
// on once it is clear; and (navd's addition) drive off only towards the grid while a whole turn
// has not shown a clear way there.
TEST(GridReentry, TurnsWhileTheSectorAheadIsBlockedAndDrivesOnceClear) {
  GridReentryOptions o;
  o.sector_width = 1.0;
  o.sector_radius = 0.6;
  EXPECT_TRUE(GridReentry::SectorClear({{0.7, 0.0}, {0.3, 0.4}, {-0.2, 0.0}}, 1.0, 0.6));  // beyond r_c, beside, behind
  EXPECT_FALSE(GridReentry::SectorClear({{0.5, 0.2}}, 1.0, 0.6));                          // 0.38 rad off, 0.54 m
  GridReentry r(o);
  EXPECT_EQ(r.Step(Pose2(), {}, std::nullopt, 0.0).left, 0.0);  // not started: no command
  r.Start(0.0);
  WheelSpeeds w = r.Step(Pose2(), {{0.4, 0.0}}, std::nullopt, 0.0);
  EXPECT_EQ(r.state(), ReentryState::kRotate);
  EXPECT_NEAR(w.left, -w.right, 1e-12);
  w = r.Step(Pose2(), {{0.0, 0.4}}, std::nullopt, 0.05);
  EXPECT_EQ(r.state(), ReentryState::kForward);
  EXPECT_GT(w.left, 0.0);
  EXPECT_EQ(w.left, w.right);
  EXPECT_FALSE(r.TimedOut(o.give_up_after - 1.0));
  EXPECT_TRUE(r.TimedOut(o.give_up_after + 1.0));
}

TEST(GridReentry, TurnsTowardsTheGridBeforeDrivingAndTakesAnyClearWayAfterAWholeTurn) {
  GridReentry r;
  r.Start(0.0);
  // Facing away from the grid (it lies behind and to the right) in open space: it turns right.
  Pose2 pose(0.0, 0.0, 0.0);
  const Point2 grid(-2.0, -1.0);
  double t = 0.0;
  WheelSpeeds w = r.Step(pose, {}, grid, t);
  EXPECT_EQ(r.state(), ReentryState::kRotate);
  EXPECT_GT(w.left, 0.0);  // right turn
  double turned = 0.0;
  while (r.state() == ReentryState::kRotate && turned < 7.0) {
    pose.theta = NormalizeAngle(pose.theta - 0.05);
    turned += 0.05;
    w = r.Step(pose, {}, grid, t += 0.05);
  }
  EXPECT_EQ(r.state(), ReentryState::kForward);
  const double bearing = std::atan2(grid.y() - pose.y, grid.x() - pose.x);
  EXPECT_LE(std::abs(NormalizeAngle(bearing - pose.theta)), r.options().max_bearing + 1e-9);
  // A wall in the way towards the grid (seen at every heading within the limits): after a whole turn
  // any clear heading will do, for relaxed_distance of driving.
  GridReentry blocked;
  blocked.Start(0.0);
  pose = Pose2(0.0, 0.0, 0.0);
  turned = 0.0;
  t = 0.0;
  auto wall = [&] {
    // A wall 0.4 m to the west of the robot, in its own frame.
    std::vector<Point2> local;
    for (double y = -2.0; y <= 2.0; y += 0.05) local.push_back(pose.inverse() * Point2(-0.4, y));
    return local;
  };
  blocked.Step(pose, wall(), Point2(-2.0, 0.0), t);
  while (blocked.state() == ReentryState::kRotate && turned < 10.0) {
    pose.theta = NormalizeAngle(pose.theta + 0.05);
    turned += 0.05;
    blocked.Step(pose, wall(), Point2(-2.0, 0.0), t += 0.05);
  }
  EXPECT_EQ(blocked.state(), ReentryState::kForward);
  EXPECT_GT(turned, 2.0 * M_PI);
  double driven = 0.0;
  while (blocked.state() == ReentryState::kForward && driven < 2.0) {
    pose = pose * Pose2(0.01, 0.0, 0.0);
    driven += 0.01;
    blocked.Step(pose, wall(), Point2(-2.0, 0.0), t += 0.05);
  }
  EXPECT_NEAR(driven, blocked.options().relaxed_distance, 0.02);  // then it turns back towards the grid
  EXPECT_GT(std::cos(pose.theta), 0.5);                           // away from the wall, not into it
}

TEST(Navigator, RejectsASecondGoalUnlessPreempting) {
  Navigator nav;
  nav.Step({0, 0, 0}, 0.0, true);
  const uint64_t first = nav.Start({{2, 0, 0}, false}, {{0, 0}, {2, 0}}, 2.0, 0.0, false);
  try {
    nav.Start({{0, 2, 0}, false}, {{0, 0}, {0, 2}}, 2.0, 0.1, false);
    FAIL() << "second goal accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kFailedPrecondition);
    EXPECT_NE(std::string(e.what()).find("rejected"), std::string::npos) << e.what();
  }
  const uint64_t second = nav.Start({{0, 2, 0}, false}, {{0, 0}, {0, 2}}, 2.0, 0.2, true);
  EXPECT_NE(first, second);
  ASSERT_TRUE(nav.ResultOf(first));
  EXPECT_EQ(nav.ResultOf(first)->outcome, Outcome::kPreempted);
  EXPECT_TRUE(nav.Cancel());
  EXPECT_EQ(nav.ResultOf(second)->outcome, Outcome::kCanceled);
  EXPECT_FALSE(nav.Cancel());
}

TEST(Navigator, StopsOnStaleSensorsAndResumes) {
  Navigator nav;
  nav.Step({0, 0, 0}, 0.0, true);
  nav.Start({{2, 0, 0}, false}, {{0, 0}, {2, 0}}, 2.0, 0.0, false);
  const WheelSpeeds stale = nav.Step({0, 0, 0}, 0.1, false);
  EXPECT_EQ(stale.left, 0.0);
  EXPECT_EQ(stale.right, 0.0);
  EXPECT_EQ(nav.Status().feedback.state, NavigationState::kStoppedStaleSensors);
  EXPECT_TRUE(nav.Status().active);
  const WheelSpeeds fresh = nav.Step({0, 0, 0}, 0.2, true);
  EXPECT_GT(fresh.left + fresh.right, 0.0);
}

TEST(Navigator, SucceedsAtTheGoal) {
  Navigator nav;
  nav.Step({0, 0, 0}, 0.0, true);
  const uint64_t id = nav.Start({{1, 0, 0}, false}, {{0, 0}, {1, 0}}, 1.0, 0.0, false);
  nav.Step({0.5, 0, 0}, 1.0, true);
  nav.Step({0.99, 0, 0}, 2.0, true);
  ASSERT_TRUE(nav.ResultOf(id));
  EXPECT_EQ(nav.ResultOf(id)->outcome, Outcome::kSucceeded);
  EXPECT_NEAR(nav.ResultOf(id)->elapsed, 2.0, 1e-12);
  EXPECT_FALSE(nav.Status().active);
}

TEST(Navigator, FailsWhenTheRobotMakesNoProgress) {
  NavigatorOptions o;
  o.progress_timeout = 5.0;
  o.max_recoveries = 0;  // nobody here runs them (the executive does)
  Navigator nav(o);
  nav.Step({0, 0, 0}, 0.0, true);
  const uint64_t id = nav.Start({{3, 0, 0}, false}, {{0, 0}, {3, 0}}, 3.0, 0.0, false);
  for (double t = 0.0; t < 6.0 && nav.Status().active; t += 0.05) nav.Step({0.5, 0, 0}, t, true);  // stuck
  ASSERT_TRUE(nav.ResultOf(id));
  EXPECT_EQ(nav.ResultOf(id)->outcome, Outcome::kFailed);
  EXPECT_NE(nav.ResultOf(id)->message.find("no progress"), std::string::npos);
}

// The office run that stood 1000 s: a box too near to plan round lay across the path, so the leg
// was replanned every second (through the box again) while the scan guard held the robot still.
TEST(Navigator, ReplanningALegDoesNotRestartItsProgressClock) {
  NavigatorOptions o;
  o.progress_timeout = 5.0;
  o.max_recoveries = 1;
  Navigator nav(o);
  nav.Step({0, 0, 0}, 0.0, true);
  nav.Start({{3, 0, 0}, false}, {{0, 0}, {3, 0}}, 3.0, 0.0, false);
  double stuck_at = -1.0;
  for (int step = 0; step < 160 && stuck_at < 0.0; ++step) {
    const double t = 0.05 * step;
    if (step % 20 == 0) {  // once a second
      ASSERT_TRUE(nav.ReplanIfBlocked([](const Point2& p) { return p.x() > 0.1; }, 2.0));
      ASSERT_TRUE(nav.LegToPlan());
      nav.SetLegPath({{0.5, 0}, {3, 0}}, 2.5, t);
    }
    nav.Step({0.5, 0, 0}, t, true);
    if (nav.TakeStuck()) stuck_at = t;
  }
  EXPECT_NEAR(stuck_at, 5.0, 0.1);
  EXPECT_EQ(nav.Status().feedback.recoveries, 1u);
}

// The office run past two panes of glass: its recoveries freed the robot at the first, and it
// stuck again at the second, 5 m on. Recoveries count by place: it may recover there too, and
// gives up only when stuck again where they were spent.
TEST(Navigator, RecoveriesSpentFurtherBackDoNotCountAgainstANewPlace) {
  NavigatorOptions o;
  o.progress_timeout = 2.0;
  o.max_recoveries = 1;
  Navigator nav(o);
  nav.Step({0, 0, 0}, 0.0, true);
  const uint64_t id = nav.Start({{6, 0, 0}, false}, {{0, 0}, {6, 0}}, 6.0, 0.0, false);
  double t = 0.0;
  int recoveries = 0;
  const auto hold = [&](double x, double seconds) {
    for (const double end = t + seconds; t < end && nav.Status().active; t += 0.05) {
      nav.Step({x, 0, 0}, t, true);
      recoveries += nav.TakeStuck();
    }
  };
  hold(0.5, 2.5);  // stuck at the first pane: a recovery
  EXPECT_EQ(recoveries, 1);
  for (double x = 0.5; x < 3.0; x += 0.1) hold(x, 0.05);  // freed, on 2.5 m
  hold(3.0, 2.5);                                         // stuck at the second: a recovery there too
  EXPECT_EQ(recoveries, 2);
  ASSERT_TRUE(nav.Status().active);
  hold(3.1, 2.5);  // stuck there again: it gives up
  EXPECT_EQ(recoveries, 2);
  ASSERT_TRUE(nav.ResultOf(id));
  EXPECT_EQ(nav.ResultOf(id)->outcome, Outcome::kFailed);
  EXPECT_NE(nav.ResultOf(id)->message.find("after 1 recoveries on this leg within 1.0 m of here"), std::string::npos)
      << nav.ResultOf(id)->message;
}

TEST(Navigator, FailsWhenSensorsStayStale) {
  NavigatorOptions o;
  o.stale_timeout = 2.0;
  Navigator nav(o);
  nav.Step({0, 0, 0}, 0.0, true);
  const uint64_t id = nav.Start({{3, 0, 0}, false}, {{0, 0}, {3, 0}}, 3.0, 0.0, false);
  for (double t = 0.0; t < 1.5; t += 0.05) nav.Step({0, 0, 0}, t, false);
  EXPECT_TRUE(nav.Status().active);  // still holding the goal
  for (double t = 1.5; t < 3.0; t += 0.05) nav.Step({0, 0, 0}, t, false);
  ASSERT_TRUE(nav.ResultOf(id));
  EXPECT_EQ(nav.ResultOf(id)->outcome, Outcome::kFailed);
  EXPECT_NE(nav.ResultOf(id)->message.find("stale"), std::string::npos);
}

TEST(OdometryLocalizer, AnchorsOdometryAtTheInitialPoseAndRejectsBadPoses) {
  localization::OdometryLocalizer loc;
  loc.SetPose({1.0, 2.0, M_PI / 2}, Eigen::Matrix3d::Zero());
  EXPECT_FALSE(loc.Estimate().valid);
  loc.AddOdometry({{5.0, 5.0, 0.0}, Eigen::Matrix3d::Zero(), 0.0});  // odom frame starts anywhere
  loc.AddOdometry({{6.0, 5.0, 0.0}, Eigen::Matrix3d::Zero(), 1.0});  // 1 m forward
  const auto e = loc.Estimate();
  EXPECT_NEAR(e.pose.x, 1.0, 1e-12);
  EXPECT_NEAR(e.pose.y, 3.0, 1e-12);
  EXPECT_NEAR(e.pose.theta, M_PI / 2, 1e-12);
  try {
    loc.SetPose({NAN, 0, 0}, Eigen::Matrix3d::Zero());
    FAIL();
  } catch (const Error& err) {
    EXPECT_EQ(err.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(err.what()).find("pose.x"), std::string::npos);
  }
  Eigen::Matrix3d bad = Eigen::Matrix3d::Identity();
  bad(0, 0) = -1;
  EXPECT_THROW(loc.SetPose({0, 0, 0}, bad), Error);
}

TEST(SimClock, FollowsTimeIgnoresReorderingAndResetsOnRestart) {
  SimClock clock;
  clock.Set(10.0);
  clock.Set(9.9);  // a reordered sample
  EXPECT_EQ(clock.Now(), 10.0);
  clock.Set(0.2);  // the simulator restarted
  EXPECT_EQ(clock.Now(), 0.2);
  EXPECT_FALSE(clock.SleepUntil(1.0, 0.01));
  EXPECT_TRUE(clock.SleepUntil(0.1, 0.01));
}

// A speed zone over the corridor y in [4, 6] of a 10 m map, 0.15 m/s.
SpeedZone Corridor() { return {"corridor", {{0.0, 4.0}, {2.0, 4.0}, {2.0, 6.0}, {0.0, 6.0}}, 0.15}; }

TEST(SpeedZones, LimitInsideAndBrakingBeforeAZoneAheadNoneBehindOrFar) {
  const SpeedZones zones({Corridor()});
  const SpeedZoneOptions o;  // 0.5 m/s^2 over 0.6 m
  const double r = 0.2;
  EXPECT_DOUBLE_EQ(zones.LimitAt({1.0, 5.0, M_PI / 2}, r, o), 0.15);
  EXPECT_DOUBLE_EQ(zones.LimitAt({1.0, 3.85, M_PI / 2}, r, o), 0.15);  // the disc reaches in
  // Facing the zone 0.4 m from its edge: the first sample whose disc touches it is 0.2 m ahead.
  EXPECT_NEAR(zones.LimitAt({1.0, 3.6, M_PI / 2}, r, o), std::sqrt(0.15 * 0.15 + 2 * 0.5 * 0.2), 1e-9);
  EXPECT_TRUE(std::isinf(zones.LimitAt({1.0, 3.6, -M_PI / 2}, r, o)));  // driving away
  EXPECT_TRUE(std::isinf(zones.LimitAt({1.0, 1.0, M_PI / 2}, r, o)));   // beyond the look-ahead
  EXPECT_TRUE(std::isinf(SpeedZones().LimitAt({1.0, 5.0, 0.0}, r, o)));
  // The tighter of two overlapping zones wins.
  SpeedZone slow = Corridor();
  slow.name = "door";
  slow.max_speed = 0.05;
  EXPECT_DOUBLE_EQ(SpeedZones({Corridor(), slow}).LimitAt({1.0, 5.0, 0.0}, r, o), 0.05);
}

TEST(SpeedZones, CapScalesBothWheelsKeepingTheTurn) {
  const WheelSpeeds w = SpeedZones::Cap({0.4, 0.2}, 0.1);
  EXPECT_DOUBLE_EQ(w.left, 0.1);
  EXPECT_DOUBLE_EQ(w.right, 0.05);
  const WheelSpeeds spin = SpeedZones::Cap({-0.3, 0.3}, 0.15);
  EXPECT_DOUBLE_EQ(spin.left, -0.15);
  EXPECT_DOUBLE_EQ(spin.right, 0.15);
  const WheelSpeeds slow = SpeedZones::Cap({0.05, 0.04}, 0.1);
  EXPECT_DOUBLE_EQ(slow.left, 0.05);
  EXPECT_DOUBLE_EQ(SpeedZones::Cap({0.5, 0.5}, std::numeric_limits<double>::infinity()).left, 0.5);
}

TEST(SpeedZones, BadZonesAreRefusedNamingTheField) {
  auto refused = [](std::vector<SpeedZone> zones, const std::string& expected) {
    try {
      SpeedZones z(std::move(zones));
      ADD_FAILURE() << "accepted; expected " << expected;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  SpeedZone z = Corridor();
  z.max_speed = 0.0;
  refused({z}, "zones[0].max_speed must be a positive number");
  z.max_speed = std::nan("");
  refused({z}, "zones[0].max_speed");
  z = Corridor();
  z.name = "bow";
  z.area = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};
  refused({Corridor(), z}, "zones[1].area is not a simple closed curve");
  z = Corridor();
  z.name = "";
  refused({z}, "zones[0].name is empty");
  refused({Corridor(), Corridor()}, "zones[1].name 'corridor' names two zones");
}

TEST(SpeedZones, WorldFilesDeclareThemAndBadOnesAreNamed) {
  const std::string map = "map: {size: [10, 10]}\nrobot: {start: [1, 1]}\n";
  const World w = ParseWorld(map +
                                 "speed_zones:\n  - {name: bay, box: [2, 2, 4, 3], max_speed: 0.2}\n"
                                 "  - {polygon: [[5, 5], [7, 5], [6, 7]], max_speed: 0.1}\n",
                             "zones.yaml", ".");
  ASSERT_EQ(w.speed_zones.size(), 2u);
  EXPECT_EQ(w.speed_zones[0].name, "bay");
  EXPECT_TRUE(PolygonContains(w.speed_zones[0].area, {3.0, 2.5}));
  EXPECT_FALSE(PolygonContains(w.speed_zones[0].area, {3.0, 3.5}));
  EXPECT_EQ(w.speed_zones[1].name, "zone 1");
  EXPECT_DOUBLE_EQ(w.speed_zones[1].max_speed, 0.1);
  for (const auto& [zones, expected] : std::vector<std::pair<std::string, std::string>>{
           {"  - {box: [2, 2, 4, 3], max_speed: -1}\n", "field 'speed_zones[0].max_speed'"},
           {"  - {box: [2, 2, 4, 3]}\n", "field 'speed_zones[0].max_speed' is missing"},
           {"  - {box: [2, 2, 4, 3], polygon: [[0, 0], [1, 0], [1, 1]], max_speed: 1}\n",
            "field 'speed_zones[0]' needs exactly one of box and polygon"},
           {"  - {box: [2, 2, 2, 3], max_speed: 1}\n", "field 'speed_zones[0].box' is not a simple closed curve"},
           {"  - {name: a, box: [2, 2, 4, 3], max_speed: 1}\n  - {name: a, box: [5, 5, 6, 6], max_speed: 1}\n",
            "field 'speed_zones[1].name'"},
       }) {
    try {
      ParseWorld(map + "speed_zones:\n" + zones, "zones.yaml", ".");
      ADD_FAILURE() << "accepted " << zones;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace navd::navigation
