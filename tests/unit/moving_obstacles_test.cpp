// Seed 000's moving obstacles without transport: detection (section 4.4) from scans cast in a
// room the map does not know a cart in, the danger level, the avoidance behaviour's choices
// (section 4.5), and plans that route around detected obstacles.
#include <gtest/gtest.h>

#include <cmath>

#include "services/common/map_store.h"
#include "services/common/ray_caster.h"
#include "services/navigation/moving_obstacle_avoidance.h"
#include "services/navigation/moving_obstacle_detector.h"
#include "services/planning/planner_catalog.h"
#include "services/planning/planning_engine.h"

namespace navd::navigation {
namespace {

// A 10 x 6 m room with walls 0.1 m thick, 5 cm cells.
OccupancyGrid Room() {
  OccupancyGrid g(200, 120, 0.05, Point2::Zero());
  g.FillBox({0, 0}, {10, 0.1});
  g.FillBox({0, 5.9}, {10, 6});
  g.FillBox({0, 0}, {0.1, 6});
  g.FillBox({9.9, 0}, {10, 6});
  return g;
}

// What a 240-degree, 683-beam laser at `pose` sees in the room with a cart of `radius` at `cart`.
localization::ScanReading ScanWithCart(const Pose2& pose, const Point2& cart, double radius) {
  OccupancyGrid world = Room();
  world.FillDisc(cart, radius);
  const RayCaster caster(world);
  localization::ScanReading scan;
  scan.angle_min = -2.0944;
  scan.angle_increment = 4.1888 / 682;
  scan.range_min = 0.02;
  scan.range_max = 4.0;
  for (int i = 0; i < 683; ++i) {
    const double a = pose.theta + scan.angle_min + i * scan.angle_increment;
    scan.ranges.push_back(static_cast<float>(caster.Cast(pose.translation(), a, scan.range_max)));
  }
  return scan;
}

MovingObstacleDetector Detector() {
  MovingObstacleDetector d;
  d.SetMap(std::make_shared<const RayCaster>(Room()));
  return d;
}

TEST(MovingObstacleDetector, FindsACartTheMapDoesNotHoldAndConfirmsItAfterHalfASecond) {
  MovingObstacleDetector d = Detector();
  const Pose2 robot(2.0, 3.0, 0.0);
  const auto found = d.Segment(ScanWithCart(robot, {4.0, 3.3}, 0.2), robot);
  ASSERT_EQ(found.size(), 1u);  // the walls match the map: nothing else
  EXPECT_LT((found[0].position - Point2(4.0, 3.3)).norm(), 0.06);
  // Enlarged by the seed's 50 % margin (0.2 m drawn in 5 cm cells reads a little wider).
  EXPECT_NEAR(found[0].radius, 0.3, 0.06);

  for (int i = 0; i <= 4; ++i) d.Update(ScanWithCart(robot, {4.0, 3.3}, 0.2), robot, 0.1 * i);
  ASSERT_EQ(d.candidates().size(), 1u);
  EXPECT_TRUE(d.confirmed().empty()) << "confirmed before Delta T_mo = 0.5 s";
  d.Update(ScanWithCart(robot, {4.0, 3.3}, 0.2), robot, 0.5);
  EXPECT_EQ(d.confirmed().size(), 1u);
  EXPECT_GT(d.confirmed()[0].probability, 0.9);
}

TEST(MovingObstacleDetector, ForgetsAGhostAndIgnoresSpecksAndFarBodies) {
  MovingObstacleDetector d = Detector();
  const Pose2 robot(2.0, 3.0, 0.0);
  d.Update(ScanWithCart(robot, {4.0, 3.3}, 0.2), robot, 0.0);  // seen once...
  ASSERT_EQ(d.candidates().size(), 1u);
  const auto empty = ScanWithCart(robot, {20.0, 20.0}, 0.2);
  d.Update(empty, robot, 0.1);  // ... p0 beta = 0.24
  EXPECT_EQ(d.candidates().size(), 1u);
  d.Update(empty, robot, 0.2);  // ... below p_min: gone
  EXPECT_TRUE(d.candidates().empty());
  // Narrower than r_min (a 2 cm post) or farther than d_max: no candidate.
  EXPECT_TRUE(d.Segment(ScanWithCart(robot, {3.0, 3.0}, 0.02), robot).empty());
  EXPECT_TRUE(d.Segment(ScanWithCart(robot, {5.8, 3.0}, 0.2), robot).empty());
}

TEST(MovingObstacleDetector, DangerRisesForAClosingCartAndNotForOneThatWaitsOrLeaves) {
  const Pose2 robot(2.0, 3.0, 0.0);
  // A cart coming head on at 0.3 m/s from 2.5 m: mu passes the avoidance threshold (~0.7) while
  // there is still room to act.
  MovingObstacleDetector closing = Detector();
  double gap_at_threshold = -1.0;
  for (int i = 0; i < 60; ++i) {
    const Point2 cart(4.5 - 0.03 * i, 3.0);
    closing.Update(ScanWithCart(robot, cart, 0.2), robot, 0.1 * i);
    if (gap_at_threshold < 0.0 && closing.danger() > 0.7) gap_at_threshold = (cart - robot.translation()).norm() - 0.4;
  }
  EXPECT_GT(gap_at_threshold, 0.2) << "danger rose too late";
  ASSERT_TRUE(closing.nearest_frontal());

  // The same cart standing still 1 m ahead of a robot that stands still: no danger.
  MovingObstacleDetector waiting = Detector();
  for (int i = 0; i < 30; ++i) waiting.Update(ScanWithCart(robot, {3.4, 3.0}, 0.2), robot, 0.1 * i);
  EXPECT_LT(waiting.danger(), 0.05);
  // One moving away: none either.
  MovingObstacleDetector leaving = Detector();
  for (int i = 0; i < 30; ++i) leaving.Update(ScanWithCart(robot, {3.0 + 0.03 * i, 3.0}, 0.2), robot, 0.1 * i);
  EXPECT_LT(leaving.danger(), 0.05);
  // One crossing the way of a robot driving at 0.4 m/s, on a collision course from the side,
  // counts before it is in front; the same cart crossing 1.5 m further on does not.
  for (const double x : {3.0, 4.5}) {
    MovingObstacleDetector crossing = Detector();
    double most = 0.0;
    for (int i = 0; i < 40; ++i) {
      const Pose2 driving(1.0 + 0.04 * i, 3.0, 0.0);
      crossing.Update(ScanWithCart(driving, {x, 1.6 + 0.03 * i}, 0.2), driving, 0.1 * i);
      most = std::max(most, crossing.danger());
    }
    if (x == 3.0) {
      EXPECT_GT(most, 0.7);
    } else {
      EXPECT_LT(most, 0.3);
    }
  }
}

AvoidanceSensing OpenAround(double rear) {
  AvoidanceSensing s;
  s.free_along = [](double) { return 3.0; };
  s.rear_free = rear;
  return s;
}

TEST(MovingObstacleAvoidance, ZonesAndTheSeedsManoeuvres) {
  MovingObstacleAvoidance a;
  EXPECT_EQ(a.Zone(1.0), 1);
  EXPECT_EQ(a.Zone(0.2), 2);
  EXPECT_EQ(a.Zone(-0.2), 3);
  EXPECT_EQ(a.Zone(-1.0), 4);

  // Zone 1 (front left) with room behind: straight back, the set distance, then stand still.
  Pose2 pose(0, 0, 0);
  a.Start(pose, {1.0, 1.2}, OpenAround(2.0), 0.0);
  EXPECT_EQ(a.phase(), AvoidancePhase::kBackingUp);
  double t = 0.0;
  for (; t < 10.0 && !a.done(); t += 0.05) {
    const WheelSpeeds w = a.Step(pose, OpenAround(2.0), t);
    pose = pose * Pose2(0.05 * 0.5 * (w.left + w.right), 0, 0);
  }
  EXPECT_TRUE(a.done());
  EXPECT_NEAR(pose.x, -a.options().backup_distance, 0.03);
  EXPECT_NEAR(pose.y, 0.0, 1e-9);

  // Zone 1 with no room to back up: turn right (away), then drive forward...
  pose = Pose2(0, 0, 0);
  a.Start(pose, {1.0, 1.2}, OpenAround(0.2), 0.0);
  EXPECT_EQ(a.phase(), AvoidancePhase::kTurning);
  const WheelSpeeds turn = a.Step(pose, OpenAround(0.2), 0.0);
  EXPECT_GT(turn.left, 0.0);
  EXPECT_LT(turn.right, 0.0);
  // ... but not with something right at the rim: turning in place would graze it.
  const WheelSpeeds touching = a.Step(pose, OpenAround(0.05), 0.05);
  EXPECT_EQ(touching.left, 0.0);
  EXPECT_EQ(touching.right, 0.0);

  // Zone 2 (head on, slightly left): step aside to the right, turning by the inner angle first.
  pose = Pose2(0, 0, 0);
  a.Start(pose, {1.0, 0.1}, OpenAround(2.0), 0.0);
  EXPECT_EQ(a.phase(), AvoidancePhase::kTurning);
  const double wheel_base = a.options().wheel_base;
  for (t = 0.0; t < 20.0 && a.phase() == AvoidancePhase::kTurning; t += 0.05) {
    const WheelSpeeds w = a.Step(pose, OpenAround(2.0), t);
    pose = pose * Pose2(0, 0, 0.05 * (w.right - w.left) / wheel_base);
  }
  EXPECT_EQ(a.phase(), AvoidancePhase::kPassing);
  EXPECT_NEAR(pose.theta, -a.options().inner_turn, 0.05);
  // A zone-2 obstacle with only the left side open: the robot steps left instead.
  AvoidanceSensing left_open = OpenAround(2.0);
  left_open.free_along = [](double bearing) { return bearing > 0.0 ? 3.0 : 0.1; };
  a.Start(Pose2(0, 0, 0), {1.0, 0.1}, left_open, 0.0);
  const WheelSpeeds left = a.Step(Pose2(0, 0, 0), left_open, 0.0);
  EXPECT_LT(left.left, 0.0);
  EXPECT_GT(left.right, 0.0);
}

// Something coming up behind while the robot backs away (a cart through the door it backs into):
// the robot stops backing back_clearance short of the rear sensor's reading and turns to pass
// instead; it does not start backing up when the whole way back does not fit.
TEST(MovingObstacleAvoidance, BackingUpStopsShortOfWhatComesUpBehind) {
  MovingObstacleAvoidance a;
  const double clearance = a.options().back_clearance;
  ASSERT_GT(clearance, a.options().min_clearance);
  a.Start(Pose2(), {1.0, 1.2}, OpenAround(2.0), 0.0);
  ASSERT_EQ(a.phase(), AvoidancePhase::kBackingUp);
  EXPECT_LT(a.Step(Pose2(), OpenAround(clearance + 0.05), 0.05).left, 0.0);  // still backing
  a.Step(Pose2(), OpenAround(clearance - 0.05), 0.10);
  EXPECT_EQ(a.phase(), AvoidancePhase::kTurning);
  a.Start(Pose2(), {1.0, 1.2}, OpenAround(a.options().backup_distance + clearance - 0.01), 0.0);
  EXPECT_EQ(a.phase(), AvoidancePhase::kTurning);
}

TEST(MovingObstacleAvoidance, StalledWheelsEndTheManoeuvre) {
  MovingObstacleAvoidance a;
  const Pose2 stuck(0, 0, 0);
  a.Start(stuck, {1.0, 1.2}, OpenAround(2.0), 0.0);
  double t = 0.0;
  for (; t < 30.0 && !a.done(); t += 0.05) a.Step(stuck, OpenAround(2.0), t);
  EXPECT_TRUE(a.done());
  EXPECT_LT(t, 2.0 * a.options().backup_distance / a.options().backup_speed + 1.5);
}

TEST(PlanningScene, GridPlannersRouteAroundMovingBodiesUnlessOneStandsOnTheGoal) {
  MapStore maps;
  maps.Set(Room(), "room");
  planning::PlanningEngineOptions options;
  options.costmap.inflation_radius = 0.3;
  planning::PlanningEngine engine(maps, options);
  planning::RegisterDefaultPlanners(engine);
  const Point2 start(1.0, 3.0), goal(9.0, 3.0);
  planning::PlanningScene scene;
  scene.moving.push_back({{5.0, 3.0}, {0.0, 0.0}, 0.3, false});
  const auto plain = engine.ComputePath(start, goal, "astar", {});
  const auto around = engine.ComputePath(start, goal, "astar", {}, {}, scene);
  EXPECT_NEAR(plain.length, 8.0, 0.01);
  EXPECT_GT(around.length, plain.length + 0.1);
  // Sampled densely, the new path keeps the body's radius plus the inflation clear.
  for (size_t i = 1; i < around.points.size(); ++i) {
    for (double f = 0.0; f <= 1.0; f += 0.02) {
      const Point2 p = around.points[i - 1] + f * (around.points[i] - around.points[i - 1]);
      EXPECT_GT((p - Point2(5.0, 3.0)).norm(), 0.3 + 0.3 - 0.06);
    }
  }
  // A body over the goal cannot be planned around: the plan ignores it rather than fail.
  planning::PlanningScene on_goal;
  on_goal.moving.push_back({goal, {0.0, 0.0}, 0.3, false});
  EXPECT_NEAR(engine.ComputePath(start, goal, "astar", {}, {}, on_goal).length, plain.length, 1e-9);
}

}  // namespace
}  // namespace navd::navigation
