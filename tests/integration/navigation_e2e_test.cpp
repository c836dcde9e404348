// End to end over real processes: navsim and navd on loopback (own DDS domain, free port), the
// robot sent to the default world's three goals through libnavclient, judged by the simulator's
// ground truth.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#include "client_lib/telemetry.h"
#include "services/common/world.h"
#include "tests/support/navd_fixture.h"

namespace navd::testing {
namespace {

void ThreeGoals(double rate) {
  StackOptions options;
  options.rate = rate;
  NavdStack stack(options);
  const auto telemetry_ptr = stack.MakeTelemetry();
  const Telemetry& telemetry = *telemetry_ptr;
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();

  const World world = DefaultWorld();
  ASSERT_EQ(world.goals.size(), 3u);
  for (const Pose2& goal : world.goals) {
    size_t feedback = 0;
    const v1::NavigationResult result = stack.client().NavigateTo(
        goal.x, goal.y, std::nullopt, [&](const v1::NavigationFeedback&) { ++feedback; }, 120.0);
    ASSERT_EQ(result.outcome(), v1::SUCCEEDED) << result.message() << "\n" << stack.Logs();
    EXPECT_GT(feedback, 0u);
    // Ground truth from the simulator, a fresh sample taken after arrival.
    const auto truth = telemetry.WaitForSimStatus(5.0);
    ASSERT_TRUE(truth) << "no simulator status over DDS";
    const double error = std::hypot(truth->x() - goal.x, truth->y() - goal.y);
    std::printf("goal (%.2f, %.2f): true position error %.3f m, estimated %.3f m, %.1f s\n", goal.x, goal.y, error,
                result.distance_to_goal(), result.elapsed());
    EXPECT_LT(error, 0.25) << "true pose (" << truth->x() << ", " << truth->y() << ")";
    EXPECT_EQ(truth->collisions(), 0u) << "the simulator reported a collision";
  }
  // The particle filter localised the robot on the laser scans.
  const auto pose = stack.client().GetPose();
  EXPECT_EQ(pose.localizer(), "amcl");
  EXPECT_GT(pose.quality(), 0.5);
  // navd's own telemetry flowed over DDS too: the pose (map frame) and the status.
  EXPECT_GT(telemetry.pose_count(), 0u);
  ASSERT_TRUE(telemetry.LatestPose());
  EXPECT_EQ(telemetry.LatestPose()->header().frame_id(), "map");
  EXPECT_NEAR(telemetry.LatestPose()->pose().pose().position().x(), world.goals.back().x, 0.2);
  EXPECT_GT(telemetry.status_count(), 0u);
  const auto status = telemetry.LatestStatus();
  ASSERT_TRUE(status);
  EXPECT_FALSE(status->active());
}

TEST(NavigationE2E, ThreeGoalsInTheDefaultWorldAtRate10) { ThreeGoals(10.0); }

// navd starts with a wrong pose (0.25 m and 0.12 rad off). The particle filter corrects it from
// the laser while the robot drives, so the robot still arrives where it was sent; dead reckoning
// would carry the initial error to the goal.
TEST(NavigationE2E, LaserLocalisationCorrectsAWrongInitialPose) {
  StackOptions options;
  options.navd_args = {"--initial-pose", "1.0", "1.15", "1.45"};  // truth: (0.8, 1.0, 1.5708)
  NavdStack stack(options);
  const auto telemetry_ptr = stack.MakeTelemetry();
  const Telemetry& telemetry = *telemetry_ptr;
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  const auto result = stack.client().NavigateTo(3.0, 2.6, std::nullopt, {}, 120.0);
  ASSERT_EQ(result.outcome(), v1::SUCCEEDED) << result.message() << stack.Logs();
  const auto truth = telemetry.WaitForSimStatus(5.0);
  ASSERT_TRUE(truth);
  const double error = std::hypot(truth->x() - 3.0, truth->y() - 2.6);
  std::printf("wrong initial pose: true position error at the goal %.3f m\n", error);
  EXPECT_LT(error, 0.12);
  EXPECT_EQ(truth->collisions(), 0u);
}

// Wake-up (seed 000 section 7), automatically: navd is told a pose metres away from the truth. The
// scans stop fitting, the executive declares the pose lost after 3 s, the wake-up behaviour takes
// the robot, relocalises over the whole map and turns in place until the estimate fits; then the
// estimate is back on the true pose.
TEST(NavigationE2E, WakeUpRelocalisesAutomaticallyWhenThePoseIsLost) {
  StackOptions options;
  options.rate = 5.0;
  NavdStack stack(options);
  std::atomic<bool> woke{false};
  TelemetryOptions topts;
  topts.dds.domain = stack.domain();
  topts.dds.name = "test";
  Telemetry telemetry(topts, [&](const navd_msgs::msg::dds_::NavStatus_& m) {
    if (m.behaviour() == "wake_up") woke = true;
  });
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  // Out of the start corridor first: along a featureless corridor no search can tell where it is.
  ASSERT_EQ(stack.client().NavigateTo(3.0, 2.6, std::nullopt, {}, 120.0).outcome(), v1::SUCCEEDED) << stack.Logs();
  ASSERT_TRUE(telemetry.WaitForSimStatus(5.0));
  stack.client().SetPose(4.0, 5.0, -1.0);  // free space metres away; truth near (3.0, 2.6)
  bool found = false;
  double error = 0, heading = 0;
  for (int i = 0; i < 300 && !found; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const auto truth = telemetry.LatestSimStatus();
    const auto pose = stack.client().GetPose();
    if (!truth) continue;
    error = std::hypot(pose.pose().x() - truth->x(), pose.pose().y() - truth->y());
    heading = std::abs(NormalizeAngle(pose.pose().theta() - truth->theta()));
    found = woke && error < 0.15 && heading < 0.1;
  }
  std::printf("wake-up: behaviour seen %d; estimate %.3f m / %.3f rad from the truth\n", woke.load(), error, heading);
  EXPECT_TRUE(woke.load()) << stack.Logs();
  EXPECT_TRUE(found) << stack.Logs();
  EXPECT_EQ(telemetry.LatestSimStatus()->collisions(), 0u);
}

// navd computes odometry itself from the wheel encoders (rt/joint_states) instead of reading the
// robot's rt/odom, and still gets the robot to its goal.
TEST(NavigationE2E, NavigatesWithOdometryFromTheWheelEncoders) {
  StackOptions options;
  options.navd_args = {"--odometry", "encoders"};
  NavdStack stack(options);
  const auto telemetry = stack.MakeTelemetry();
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  const auto result = stack.client().NavigateTo(3.0, 2.6, std::nullopt, {}, 120.0);
  ASSERT_EQ(result.outcome(), v1::SUCCEEDED) << result.message() << stack.Logs();
  const auto truth = telemetry->WaitForSimStatus(5.0);
  ASSERT_TRUE(truth);
  EXPECT_LT(std::hypot(truth->x() - 3.0, truth->y() - 2.6), 0.12);
  EXPECT_EQ(truth->collisions(), 0u);
}

TEST(NavigationE2E, StreamReportsProgressAndCancelStopsTheRobot) {
  StackOptions options;
  options.sim_args = {"--command-timeout", "60"};  // only navd's stop can halt the robot
  NavdStack stack(options);
  const auto telemetry_ptr = stack.MakeTelemetry();
  const Telemetry& telemetry = *telemetry_ptr;
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();

  std::thread canceller([&] {
    // Let the robot get going, then cancel through a second call.
    for (int i = 0; i < 200 && !stack.client().GetStatus().active(); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    Client other({stack.address(), 5.0});
    EXPECT_TRUE(other.Cancel());
  });
  std::vector<double> remaining;
  const auto result = stack.client().NavigateTo(
      8.8, 8.8, std::nullopt, [&](const v1::NavigationFeedback& f) { remaining.push_back(f.distance_remaining()); },
      60.0);
  canceller.join();
  EXPECT_EQ(result.outcome(), v1::CANCELED);
  ASSERT_FALSE(remaining.empty());
  // The robot stops: its true position no longer changes.
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_TRUE(RobotStandsStill(telemetry, 0.5));
  EXPECT_FALSE(stack.client().GetStatus().active());
}

}  // namespace
}  // namespace navd::testing
