// Seed 004's reflexes: the five groups, winner-take-all, the three levels and the vector sum, then
// the executive with its real planner and navigator driving at a pane only the sonar finds.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "services/common/diff_drive.h"
#include "services/common/map_store.h"
#include "services/common/ray_caster.h"
#include "services/common/sonar_ring.h"
#include "services/localization/odometry_localizer.h"
#include "services/navigation/navigation_executive.h"
#include "services/navigation/sonar_reflex.h"
#include "services/planning/planner_catalog.h"
#include "simulator/range_sensor_array.h"

namespace navd::navigation {
namespace {

constexpr double kDeg = M_PI / 180.0;

TEST(SonarReflex, ThePioneerRingsFrontHalfFormsFiveGroups) {
  const SonarReflex reflex;
  std::vector<SonarGroup> groups;
  for (double a : PioneerSonarAngles()) groups.push_back(reflex.GroupOf(a));
  using G = SonarGroup;
  const std::vector<SonarGroup> expected = {
      G::kLeft,  G::kFrontLeft, G::kFrontLeft, G::kFront, G::kFront, G::kFrontRight, G::kFrontRight, G::kRight,
      G::kRight, G::kNone,      G::kNone,      G::kNone,  G::kNone,  G::kNone,       G::kNone,       G::kLeft};
  EXPECT_EQ(groups, expected);
}

TEST(SonarReflex, TheNearestGroupWinsAndItsRangeSetsOneOfThreeLevels) {
  const SonarReflex reflex;
  EXPECT_EQ(reflex.Respond({}, 0.0).level, 0);
  EXPECT_EQ(reflex.Respond({{90 * kDeg, 2.0}, {10 * kDeg, 0.9}}, 0.0).level, 0);  // nothing close
  EXPECT_EQ(reflex.Respond({{-150 * kDeg, 0.1}}, 0.0).level, 0);                  // behind: no part

  // A wall on the left at 0.6 m and a post front-right at 0.3 m: the post wins, level 2.
  ReflexResponse r = reflex.Respond({{90 * kDeg, 0.6}, {-30 * kDeg, 0.3}}, 0.0);
  EXPECT_EQ(r.group, SonarGroup::kFrontRight);
  EXPECT_EQ(r.level, 2);
  EXPECT_NEAR(r.orientation, 120 * kDeg, 1e-9);  // away from it: left and back
  EXPECT_NEAR(r.magnitude, 1.0, 1e-9);
  r = reflex.Respond({{90 * kDeg, 0.6}}, 0.0);
  EXPECT_EQ(r.group, SonarGroup::kLeft);
  EXPECT_EQ(r.level, 1);
  EXPECT_NEAR(r.orientation, -90 * kDeg, 1e-9);
  r = reflex.Respond({{50 * kDeg, 0.2}}, 0.0);
  EXPECT_EQ(r.level, 3);
  EXPECT_NEAR(r.magnitude, 3.0, 1e-9);

  // FRONT: away from the nearer of its two sensors; a tie goes the subgoal's way.
  EXPECT_LT(reflex.Respond({{10 * kDeg, 0.4}, {-10 * kDeg, 0.5}}, 0.0).orientation, 0.0);  // obstacle left: go right
  EXPECT_GT(reflex.Respond({{10 * kDeg, 0.5}, {-10 * kDeg, 0.4}}, 0.0).orientation, 0.0);
  EXPECT_GT(reflex.Respond({{10 * kDeg, 0.4}, {-10 * kDeg, 0.4}}, 0.3).orientation, 0.0);
  EXPECT_LT(reflex.Respond({{10 * kDeg, 0.4}, {-10 * kDeg, 0.4}}, -0.3).orientation, 0.0);
}

TEST(SonarReflex, TheVectorSumSteersAwayAndSlowsOnlyWhenThereIsAStimulus) {
  const SonarReflex reflex;
  const WheelSpeeds ahead{0.5, 0.5};
  // No stimulus: pure navigation.
  const WheelSpeeds same = SonarReflex::Blend(ahead, 0.0, reflex.Respond({}, 0.0), 1.0, 0.5);
  EXPECT_EQ(same.left, 0.5);
  EXPECT_EQ(same.right, 0.5);
  // A weak stimulus on the left nudges right at full speed.
  const WheelSpeeds nudge = SonarReflex::Blend(ahead, 0.0, reflex.Respond({{90 * kDeg, 0.6}}, 0.0), 1.0, 0.5);
  EXPECT_GT(nudge.left, nudge.right);
  EXPECT_NEAR(ToTwist(nudge, 0.33).omega,
              ToTwist(ClampWheels({0.5 + 0.5 * std::atan(0.3), 0.5 - 0.5 * std::atan(0.3)}, 0.5), 0.33).omega, 1e-9);
  // Something urgent front-left: the sum points back and right; the robot turns right on the spot.
  const WheelSpeeds urgent = SonarReflex::Blend(ahead, 0.0, reflex.Respond({{30 * kDeg, 0.2}}, 0.0), 1.0, 0.5);
  EXPECT_NEAR(ToTwist(urgent, 0.33).v, 0.0, 1e-9);
  EXPECT_LT(ToTwist(urgent, 0.33).omega, -1.0);
  // Turning in place is left alone.
  const WheelSpeeds turning = SonarReflex::Blend({-0.2, 0.2}, 1.0, reflex.Respond({{30 * kDeg, 0.2}}, 1.0), 1.0, 0.5);
  EXPECT_EQ(turning.left, -0.2);
}

// The executive on a 6 x 5 m open floor (nothing mapped) with a 0.3 m glass pane at (3, 2.5),
// straight across the path from (1, 2.5) to (5, 2.5): no laser sees it, the Pioneer ring does.
struct PaneRun {
  double closest = 1e9;  // m between the robot's rim and the pane
  bool reached = false;
  uint32_t reflexes = 0;
  std::set<std::string> seen;
};
PaneRun DriveAtAPane(bool reflexes) {
  NavigatorOptions options;
  options.reflex.enabled = reflexes;
  MapStore maps;
  maps.Set(OccupancyGrid(120, 100, 0.05, Point2(0.0, 0.0)), "open");
  planning::PlanningEngine planning{maps, {}};
  planning::RegisterDefaultPlanners(planning);
  localization::OdometryLocalizer localizer{Pose2(1.0, 2.5, 0.0)};
  SimClock clock;
  NavigationExecutive executive{planning, localizer, clock, options};
  OccupancyGrid world(120, 100, 0.05, Point2(0.0, 0.0));
  const Box pane{{2.85, 2.35}, {3.15, 2.65}};
  world.FillBox(pane.min, pane.max);
  const RayCaster truth(world);
  const sim::RangeSensorArray ring(sim::PioneerSonarRing(0.2));
  std::mt19937_64 rng(3);
  Pose2 odom(0.0, 0.0, 0.0);
  PaneRun run;
  std::vector<SonarEcho> echoes;
  uint64_t id = 0;
  for (int i = 0; i < 800; ++i) {
    const double t = i * 0.05;
    clock.Set(t);
    localizer.AddOdometry({odom, Eigen::Matrix3d::Zero(), t});
    const Pose2 pose = localizer.Estimate().pose;  // exact: odometry without noise
    if (i % 2 == 0) {                              // the ring at 10 Hz
      const std::vector<float> ranges = ring.Read(pose, truth, {}, -1, rng);
      echoes.clear();
      for (size_t k = 0; k < ranges.size(); ++k)
        if (ranges[k] < kPioneerSonarRangeMax) echoes.push_back({PioneerSonarAngles()[k], ranges[k]});
    }
    ExecutiveInputs in;
    in.sonar = &echoes;
    const WheelSpeeds w = executive.Step(in, t);
    if (i == 0) id = executive.Navigate({Pose2(5.0, 2.5, 0.0), false, "", false});
    const NavigationStatus s = executive.navigator().Status();
    if (!s.feedback.reflex.empty()) run.seen.insert(s.feedback.reflex);
    run.reflexes = std::max(run.reflexes, s.feedback.reflexes);
    odom = IntegrateDiffDrive(odom, w.left * 0.05, w.right * 0.05, options.follower.wheel_base);
    const Point2 p = localizer.Estimate().pose.translation();
    const Point2 nearest(std::clamp(p.x(), pane.min.x(), pane.max.x()), std::clamp(p.y(), pane.min.y(), pane.max.y()));
    run.closest = std::min(run.closest, Distance(p, nearest) - 0.2);
    if (run.closest < 0.0) break;  // touched it
    if (const auto result = executive.navigator().ResultOf(id)) {
      run.reached = result->outcome == Outcome::kSucceeded;
      break;
    }
  }
  return run;
}

TEST(NavigationExecutive, SonarReflexesSteerRoundAPaneTheMapAndLaserMiss) {
  const PaneRun with = DriveAtAPane(true);
  EXPECT_TRUE(with.reached);
  EXPECT_GT(with.closest, 0.0);
  EXPECT_GE(with.reflexes, 1u);
  EXPECT_FALSE(with.seen.empty());
  for (const std::string& s : with.seen) std::printf("reflex: %s\n", s.c_str());
  std::printf("closest %.3f m, %u reflexes\n", with.closest, with.reflexes);
  const PaneRun without = DriveAtAPane(false);
  EXPECT_LT(without.closest, 0.0);  // straight into it
  EXPECT_EQ(without.reflexes, 0u);
}

}  // namespace
}  // namespace navd::navigation
