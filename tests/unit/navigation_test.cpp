// The seed-000 path follower, differential-drive kinematics, and the navigator's goal life cycle.
#include <gtest/gtest.h>

#include <cmath>

#include "services/common/clock.h"
#include "services/common/diff_drive.h"
#include "services/common/error.h"
#include "services/localization/odometry_localizer.h"
#include "services/navigation/navigator.h"
#include "services/navigation/path_follower.h"

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
  Navigator nav(o);
  nav.Step({0, 0, 0}, 0.0, true);
  const uint64_t id = nav.Start({{3, 0, 0}, false}, {{0, 0}, {3, 0}}, 3.0, 0.0, false);
  for (double t = 0.0; t < 6.0 && nav.Status().active; t += 0.05) nav.Step({0.5, 0, 0}, t, true);  // stuck
  ASSERT_TRUE(nav.ResultOf(id));
  EXPECT_EQ(nav.ResultOf(id)->outcome, Outcome::kFailed);
  EXPECT_NE(nav.ResultOf(id)->message.find("no progress"), std::string::npos);
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

}  // namespace
}  // namespace navd::navigation
