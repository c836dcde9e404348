// Book chapter 7's unicycle planned with OMPL's control planners under the Eq. 15 cost.
#include <gtest/gtest.h>

#include "services/common/error.h"
#include "services/planning/kinodynamic_planner.h"

namespace navd::planning {
namespace {

// An empty 10 x 6 m room (walls 10 cm thick), 5 cm cells; optionally a 2 x 2 m block in the middle.
Costmap Room(bool block) {
  OccupancyGrid g(200, 120, 0.05, Point2::Zero());
  g.FillBox({0.0, 0.0}, {10.0, 0.1});
  g.FillBox({0.0, 5.9}, {10.0, 6.0});
  g.FillBox({0.0, 0.0}, {0.1, 6.0});
  g.FillBox({9.9, 0.0}, {10.0, 6.0});
  if (block) g.FillBox({4.0, 2.0}, {6.0, 4.0});
  return Costmap(std::make_shared<const OccupancyGrid>(std::move(g)), CostmapOptions{0.3, true, 0.5, 3.0});
}

KinodynamicRequest LeftToRight() {
  KinodynamicRequest r;
  r.start = {1.0, 3.0};
  r.goal = {9.0, 3.0};
  r.time_limit = 0.4;
  return r;
}

// The trajectory obeys Eq. 10 within the limits: speeds, accelerations, steps, time.
void ExpectDynamicallyFeasible(const Costmap& cm, const KinodynamicRequest& r, const KinodynamicTrajectory& t) {
  ASSERT_GE(t.points.size(), 2u);
  EXPECT_LT(Distance(t.points.front(), r.start), 1e-9);
  EXPECT_LE(Distance(t.points.back(), r.goal), r.goal_tolerance + 1e-9);
  for (size_t i = 0; i < t.points.size(); ++i) {
    EXPECT_FALSE(cm.IsLethal(cm.grid().CellOf(t.points[i]))) << "point " << i;
    EXPECT_GE(t.speeds[i], -1e-12);
    EXPECT_LE(t.speeds[i], r.limits.max_speed + 1e-12);
    if (i == 0) continue;
    const double dt = t.times[i] - t.times[i - 1];
    ASSERT_GT(dt, 0.0);
    EXPECT_LE(Distance(t.points[i - 1], t.points[i]), r.limits.max_speed * dt + 1e-9);
    EXPECT_LE(std::abs(t.speeds[i] - t.speeds[i - 1]), r.limits.max_accel * dt + 1e-9);
  }
}

double ClosestApproach(const KinodynamicTrajectory& t, const MovingBody& b) {
  double closest = 1e9;
  for (size_t i = 0; i < t.points.size(); ++i)
    closest = std::min(closest, Distance(t.points[i], b.position + t.times[i] * b.velocity));
  return closest;
}

TEST(Kinodynamic, ReachesTheGoalAroundAnObstacleWithinTheUnicycleLimits) {
  const Costmap cm = Room(true);
  const KinodynamicRequest r = LeftToRight();
  const KinodynamicTrajectory t = PlanKinodynamic(cm, r, {});
  ExpectDynamicallyFeasible(cm, r, t);
  EXPECT_GT(t.tree_size, 10u);
  // At least the 8 m at top speed, and no dawdling.
  EXPECT_GE(t.times.back(), 8.0 / r.limits.max_speed - 1.0);
  EXPECT_LT(t.times.back(), 60.0);
  EXPECT_NEAR(t.cost, TrajectoryCost(cm, r, {}, t.points, t.times), 1e-9);
}

TEST(Kinodynamic, KeepsOutOfAStandingPersonsPersonalZone) {
  const Costmap cm = Room(false);
  const MovingBody person{{5.0, 3.0}, {0.0, 0.0}, 0.25, true};
  KinodynamicRequest aware = LeftToRight();
  KinodynamicRequest blind = LeftToRight();  // the person only as a body to miss
  blind.people_model.parallel_weight = blind.people_model.perpendicular_weight = blind.people_model.rear_weight = 0.0;
  const KinodynamicTrajectory with_comfort = PlanKinodynamic(cm, aware, {person});
  const KinodynamicTrajectory without = PlanKinodynamic(cm, blind, {person});
  ExpectDynamicallyFeasible(cm, aware, with_comfort);
  ExpectDynamicallyFeasible(cm, blind, without);
  const double near_aware = ClosestApproach(with_comfort, person), near_blind = ClosestApproach(without, person);
  EXPECT_GE(near_blind, person.radius + cm.options().inflation_radius);  // never touches
  EXPECT_GT(near_aware, 1.0) << "blind: " << near_blind;                 // outside most of the personal zone (1.2 m)
  // The comfort costs what it saves: the aware trajectory is cheaper under the aware cost.
  EXPECT_LT(TrajectoryCost(cm, aware, {person}, with_comfort.points, with_comfort.times),
            TrajectoryCost(cm, aware, {person}, without.points, without.times) + 1e-9);
}

TEST(Kinodynamic, PassesAPersonWalkingTowardsTheRobot) {
  const Costmap cm = Room(false);
  const MovingBody person{{8.0, 3.0}, {-0.4, 0.0}, 0.25, true};
  const KinodynamicRequest r = LeftToRight();
  const KinodynamicTrajectory t = PlanKinodynamic(cm, r, {person});
  ExpectDynamicallyFeasible(cm, r, t);
  EXPECT_GT(ClosestApproach(t, person), 0.9);
}

TEST(Kinodynamic, BadInputUnreachableGoalsAndDeadlines) {
  const Costmap cm = Room(false);
  KinodynamicRequest r = LeftToRight();
  r.start_speed = 2.0;
  try {
    PlanKinodynamic(cm, r, {});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(e.what()).find("start_speed"), std::string::npos);
  }
  r = LeftToRight();
  r.goal = {9.0, 3.0};
  r.time_limit = 0.2;
  const MovingBody blocker{{9.0, 3.0}, {0.0, 0.0}, 0.5, false};  // stands on the goal
  try {
    PlanKinodynamic(cm, r, {blocker});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNotFound) << e.what();
  }
  try {
    PlanKinodynamic(cm, LeftToRight(), {}, [] { return true; });
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kDeadlineExceeded);
  }
}

}  // namespace
}  // namespace navd::planning
