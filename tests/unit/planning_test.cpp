// A*, Dijkstra, inflation and the planning engine's checks, on small hand-made grids.
#include <gtest/gtest.h>

#include <cmath>

#include "services/common/error.h"
#include "services/common/map_store.h"
#include "services/planning/costmap.h"
#include "services/planning/elastic_band.h"
#include "services/planning/grid_astar_planner.h"
#include "services/planning/planner_catalog.h"
#include "services/planning/planning_engine.h"
#include "services/planning/velocity_profile.h"

namespace navd::planning {
namespace {

std::shared_ptr<const OccupancyGrid> Grid(int w, int h, double res = 1.0) {
  return std::make_shared<OccupancyGrid>(w, h, res, Point2(0, 0));
}

CellPath PlanCells(const Costmap& cm, CellIndex s, CellIndex g, bool dijkstra = false, double diagonal = 1.0) {
  return GridAStarPlanner(dijkstra).Plan(cm, s, g, {{"diagonal", diagonal}, {"cost_weight", 0}, {"smooth", 0}}, {});
}

double CellPathLength(const CellPath& p) {
  double len = 0;
  for (size_t i = 1; i < p.cells.size(); ++i)
    len += std::hypot(p.cells[i].x - p.cells[i - 1].x, p.cells[i].y - p.cells[i - 1].y);
  return len;
}

TEST(Costmap, InflatesByRadiusAndNoFurther) {
  auto g = std::make_shared<OccupancyGrid>(21, 21, 0.1, Point2(0, 0));
  auto grid = std::const_pointer_cast<OccupancyGrid>(g);
  grid->set({10, 10}, OccupancyGrid::kOccupied);
  Costmap cm(g, {0.3, true});
  EXPECT_TRUE(cm.IsLethal({10, 10}));
  EXPECT_TRUE(cm.IsLethal({13, 10}));   // 0.3 m away
  EXPECT_FALSE(cm.IsLethal({14, 10}));  // 0.4 m
  EXPECT_TRUE(cm.IsLethal({12, 12}));   // 0.28 m
  EXPECT_FALSE(cm.IsLethal({13, 12}));  // 0.36 m
}

TEST(Costmap, CostDecaysExponentiallyBeyondTheInflation) {
  auto grid = std::make_shared<OccupancyGrid>(41, 1, 0.1, Point2(0, 0));
  grid->set({0, 0}, OccupancyGrid::kOccupied);
  Costmap cm(grid, {0.3, true, 0.5, 3.0});
  EXPECT_TRUE(cm.IsLethal({3, 0}));
  EXPECT_FALSE(cm.IsLethal({4, 0}));
  EXPECT_EQ(cm.cost({4, 0}), std::lround(252 * std::exp(-3.0 * 0.1)));
  EXPECT_EQ(cm.cost({7, 0}), std::lround(252 * std::exp(-3.0 * 0.4)));
  EXPECT_EQ(cm.cost({8, 0}), 0);                          // 0.8 m: beyond inflation + decay
  EXPECT_EQ(Costmap(grid, {0.3, true}).cost({4, 0}), 0);  // no decay layer by default
}

TEST(Costmap, UnknownSpacePolicy) {
  auto grid = std::make_shared<OccupancyGrid>(5, 5, 1.0, Point2(0, 0));
  grid->set({2, 2}, OccupancyGrid::kUnknown);
  EXPECT_TRUE(Costmap(grid, {0.0, true}).IsLethal({2, 2}));
  EXPECT_FALSE(Costmap(grid, {0.0, false}).IsLethal({2, 2}));
}

TEST(GridAStar, OpenGridPathIsOctileOptimal) {
  auto g = Grid(30, 20);
  Costmap cm(g, {0.0, true});
  const CellPath p = PlanCells(cm, {0, 0}, {25, 10});
  ASSERT_FALSE(p.cells.empty());
  EXPECT_EQ(p.cells.front(), (CellIndex{0, 0}));
  EXPECT_EQ(p.cells.back(), (CellIndex{25, 10}));
  EXPECT_NEAR(CellPathLength(p), 15 + 10 * std::sqrt(2.0), 1e-6);
}

TEST(GridAStar, FourConnectedPathIsManhattan) {
  auto g = Grid(30, 20);
  Costmap cm(g, {0.0, true});
  EXPECT_NEAR(CellPathLength(PlanCells(cm, {0, 0}, {25, 10}, false, 0.0)), 35.0, 1e-9);
}

TEST(GridAStar, DijkstraFindsTheSameLengthWithMoreExpansions) {
  auto grid = std::make_shared<OccupancyGrid>(40, 40, 1.0, Point2(0, 0));
  for (int y = 0; y < 30; ++y) grid->set({20, y}, OccupancyGrid::kOccupied);
  Costmap cm(grid, {0.0, true});
  const CellPath a = PlanCells(cm, {2, 2}, {38, 2});
  const CellPath d = PlanCells(cm, {2, 2}, {38, 2}, true);
  ASSERT_FALSE(a.cells.empty());
  EXPECT_NEAR(CellPathLength(a), CellPathLength(d), 1e-4);
  EXPECT_LT(a.expansions, d.expansions);
}

TEST(GridAStar, DoesNotCutCorners) {
  auto grid = std::make_shared<OccupancyGrid>(3, 3, 1.0, Point2(0, 0));
  // Two cells touching diagonally block the diagonal between them.
  grid->set({1, 0}, OccupancyGrid::kOccupied);
  grid->set({0, 1}, OccupancyGrid::kOccupied);
  Costmap cm(grid, {0.0, true});
  EXPECT_TRUE(PlanCells(cm, {0, 0}, {2, 2}).cells.empty());
}

TEST(GridAStar, WallWithoutGapHasNoPath) {
  auto grid = std::make_shared<OccupancyGrid>(10, 10, 1.0, Point2(0, 0));
  for (int y = 0; y < 10; ++y) grid->set({5, y}, OccupancyGrid::kOccupied);
  Costmap cm(grid, {0.0, true});
  EXPECT_TRUE(PlanCells(cm, {1, 1}, {8, 8}).cells.empty());
}

TEST(GridAStar, StopsWhenAsked) {
  auto g = Grid(300, 300);
  Costmap cm(g, {0.0, true});
  try {
    GridAStarPlanner().Plan(cm, {0, 0}, {299, 299}, {{"diagonal", 1}, {"cost_weight", 0}, {"smooth", 0}},
                            [] { return true; });
    FAIL() << "expected a deadline error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kDeadlineExceeded);
  }
}

class EngineTest : public ::testing::Test {
 protected:
  void SetUp() override {
    OccupancyGrid grid(100, 100, 0.1, Point2(0, 0));
    grid.FillBox({4.0, 0.0}, {4.2, 8.0});  // a wall with a 2 m gap at the top
    maps.Set(std::move(grid), "test");
    RegisterDefaultPlanners(engine);
  }
  ErrorCode CodeOf(const std::function<void()>& f) {
    try {
      f();
    } catch (const Error& e) {
      message = e.what();
      return e.code();
    }
    return ErrorCode::kInternal;
  }
  MapStore maps;
  PlanningEngine engine{
      maps, PlanningEngineOptions{
                .costmap = {0.3, true}, .default_planner = "astar", .start_recovery_radius = 0.5, .velocity = {}}};
  std::string message;
};

TEST_F(EngineTest, PlansAroundTheWallWithShortcutPath) {
  const PathPlan p = engine.ComputePath({1, 1}, {8, 1}, "", {});
  EXPECT_EQ(p.planner, "astar");
  EXPECT_EQ(p.points.front(), Point2(1, 1));
  EXPECT_EQ(p.points.back(), Point2(8, 1));
  EXPECT_LE(p.points.size(), 5u);  // straight segments, not a staircase of cells
  // Around the wall's end at y=8 plus inflation: at least 2 * hypot(3, 7.3).
  EXPECT_GT(p.length, 2 * std::hypot(3.0, 7.3) - 0.1);
  EXPECT_LT(p.length, 2 * std::hypot(3.3, 7.5) + 0.3);
  auto cm = engine.CurrentCostmap();
  for (size_t i = 1; i < p.points.size(); ++i) EXPECT_TRUE(cm->SegmentFree(p.points[i - 1], p.points[i]));
}

// The elastic band (book ch. 9 R-snake) rounds the shortcut path's sharp turn around the wall's end:
// the band stays free on the costmap, keeps its end points and about its length, and the
// chapter's velocity profile gets through the rounded turn faster.
TEST_F(EngineTest, ElasticBandRoundsTheTurnsAndTheRobotGetsThroughFaster) {
  const PathPlan sharp = engine.ComputePath({1, 1}, {8, 1}, "", {});
  const PathPlan band = engine.ComputePath({1, 1}, {8, 1}, "", {{"elastic_band", 1.0}});
  EXPECT_EQ(band.points.front(), Point2(1, 1));
  EXPECT_EQ(band.points.back(), Point2(8, 1));
  auto cm = engine.CurrentCostmap();
  for (size_t i = 1; i < band.points.size(); ++i) EXPECT_TRUE(cm->SegmentFree(band.points[i - 1], band.points[i]));
  std::printf("elastic band: max turn %.2f -> %.2f rad, length %.2f -> %.2f m, profile %.2f -> %.2f s\n",
              MaxTurn(sharp.points), MaxTurn(band.points), sharp.length, band.length, sharp.duration, band.duration);
  EXPECT_LT(MaxTurn(band.points), 0.35);
  EXPECT_GT(MaxTurn(sharp.points), 0.9);
  EXPECT_LT(band.length, sharp.length * 1.05);
  EXPECT_LT(band.duration, sharp.duration);
  EXPECT_EQ(CodeOf([&] {
              engine.ComputePath({1, 1}, {8, 1}, "", {{"elastic_band", 2.0}});
            }),
            ErrorCode::kInvalidArgument);
  EXPECT_NE(message.find("elastic_band"), std::string::npos) << message;
}

TEST_F(EngineTest, RejectsNonFiniteCoordinates) {
  EXPECT_EQ(CodeOf([&] { engine.ComputePath({NAN, 1}, {8, 1}, "", {}); }), ErrorCode::kInvalidArgument);
  EXPECT_NE(message.find("start.x"), std::string::npos) << message;
  EXPECT_EQ(CodeOf([&] { engine.ComputePath({1, 1}, {8, INFINITY}, "", {}); }), ErrorCode::kInvalidArgument);
  EXPECT_NE(message.find("goal.y"), std::string::npos) << message;
}

TEST_F(EngineTest, RejectsGoalOutsideTheMap) {
  EXPECT_EQ(CodeOf([&] { engine.ComputePath({1, 1}, {12, 1}, "", {}); }), ErrorCode::kInvalidArgument);
  EXPECT_NE(message.find("goal"), std::string::npos);
  EXPECT_NE(message.find("outside the map"), std::string::npos) << message;
}

TEST_F(EngineTest, RejectsGoalInsideAnObstacleOrItsInflation) {
  EXPECT_EQ(CodeOf([&] { engine.ComputePath({1, 1}, {4.1, 3}, "", {}); }), ErrorCode::kInvalidArgument);
  EXPECT_NE(message.find("inside an obstacle"), std::string::npos) << message;
  EXPECT_EQ(CodeOf([&] { engine.ComputePath({1, 1}, {3.85, 3}, "", {}); }), ErrorCode::kInvalidArgument);
  EXPECT_NE(message.find("goal (3.85, 3.00) is within 0.30 m of an obstacle"), std::string::npos) << message;
}

TEST_F(EngineTest, RejectsUnknownPlannerAndOption) {
  EXPECT_EQ(CodeOf([&] { engine.ComputePath({1, 1}, {8, 1}, "rrt_magic", {}); }), ErrorCode::kInvalidArgument);
  EXPECT_NE(message.find("rrt_magic"), std::string::npos);
  EXPECT_NE(message.find("astar"), std::string::npos) << "lists the known planners: " << message;
  EXPECT_EQ(CodeOf([&] { engine.ComputePath({1, 1}, {8, 1}, "astar", {{"speed", 1}}); }), ErrorCode::kInvalidArgument);
  EXPECT_NE(message.find("speed"), std::string::npos) << message;
}

TEST_F(EngineTest, RejectsOptionValuesOutsideTheirDomain) {
  EXPECT_EQ(CodeOf([&] {
              engine.ComputePath({1, 1}, {8, 1}, "astar", {{"diagonal", 0.5}});
            }),
            ErrorCode::kInvalidArgument);
  EXPECT_NE(message.find("diagonal"), std::string::npos) << message;
  EXPECT_EQ(CodeOf([&] { engine.ComputePath({1, 1}, {8, 1}, "astar", {{"smooth", 7}}); }), ErrorCode::kInvalidArgument);
  EXPECT_NE(message.find("smooth"), std::string::npos) << message;
}

TEST_F(EngineTest, MovesAStartInTheInflationZoneOut) {
  const PathPlan p = engine.ComputePath({3.85, 1}, {1, 1}, "astar", {});
  EXPECT_EQ(p.points.front(), Point2(3.85, 1));
  EXPECT_EQ(p.points.back(), Point2(1, 1));
}

TEST_F(EngineTest, ReportsNoPathAsNotFound) {
  OccupancyGrid grid(100, 100, 0.1, Point2(0, 0));
  grid.FillBox({4.0, 0.0}, {4.2, 10.0});
  maps.Set(std::move(grid), "closed");
  EXPECT_EQ(CodeOf([&] { engine.ComputePath({1, 1}, {8, 1}, "", {}); }), ErrorCode::kNotFound);
}

TEST_F(EngineTest, PlansThroughWaypointsAndNamesTheBadOne) {
  const PathPlan a = engine.ComputePath({1, 1}, {8, 1}, "", {});
  const PathPlan b = engine.ComputePath({8, 1}, {8, 9}, "", {});
  const PathPlan through = engine.ComputePathThroughPoses({1, 1}, {{8, 1}, {8, 9}}, "", {});
  EXPECT_NEAR(through.length, a.length + b.length, 1e-9);
  EXPECT_EQ(through.points.size(), a.points.size() + b.points.size() - 1);
  EXPECT_EQ(CodeOf([&] {
              engine.ComputePathThroughPoses({1, 1}, {{8, 1}, {4.1, 3}, {8, 9}}, "", {});
            }),
            ErrorCode::kInvalidArgument);
  EXPECT_NE(message.find("waypoints[1]"), std::string::npos) << message;
  EXPECT_EQ(CodeOf([&] { engine.ComputePathThroughPoses({1, 1}, {}, "", {}); }), ErrorCode::kInvalidArgument);
  EXPECT_NE(message.find("waypoints"), std::string::npos) << message;
}

TEST_F(EngineTest, ListsPlannersWithOptions) {
  const auto planners = engine.Planners();
  ASSERT_EQ(planners.size(), 17u);
  EXPECT_EQ(planners[0].name, "astar");
  EXPECT_TRUE(planners[0].is_default);
  EXPECT_EQ(planners[1].name, "dijkstra");
  bool has_smooth = false;
  for (const auto& o : planners[0].options) has_smooth |= o.name == "smooth";
  EXPECT_TRUE(has_smooth);
}

TEST(Engine, WithoutAMapFailsPrecondition) {
  MapStore maps;
  PlanningEngine engine(maps, {});
  engine.Register(std::make_unique<GridAStarPlanner>());
  try {
    engine.ComputePath({1, 1}, {2, 2}, "", {});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kFailedPrecondition);
  }
}

// Book chapter 9's velocity profile on a straight 10 m line: accelerate at a, cruise at the top
// speed, brake to rest at the end: 10 / v + v / a seconds exactly.
TEST(VelocityProfile, StraightLineIsATrapezoidEndingAtRest) {
  VelocityLimits l;
  l.max_speed = 0.8;
  l.max_acceleration = 0.5;
  const VelocityProfile p = TimeOptimalProfile({{0, 0}, {10, 0}}, l);
  // Exact on every step but the two where the ramps meet the top speed between grid points.
  EXPECT_NEAR(p.duration, 10.0 / 0.8 + 0.8 / 0.5, 1e-3);
  EXPECT_DOUBLE_EQ(p.speed.front(), 0.0);
  EXPECT_DOUBLE_EQ(p.speed.back(), 0.0);
  EXPECT_NEAR(p.speed[p.speed.size() / 2], 0.8, 1e-12);
  EXPECT_NEAR(p.arc.back(), 10.0, 1e-9);
  // Never faster than the limits allow between neighbouring points (Eqs. 15-16).
  for (size_t i = 1; i < p.speed.size(); ++i) {
    const double ds = p.arc[i] - p.arc[i - 1];
    EXPECT_LE(std::abs(p.speed[i] * p.speed[i] - p.speed[i - 1] * p.speed[i - 1]), 2 * l.max_acceleration * ds + 1e-9);
  }
  l.start_speed = 0.3;
  EXPECT_NEAR(TimeOptimalProfile({{0, 0}, {10, 0}}, l).speed.front(), 0.3, 1e-12);
}

// On a circle of radius R the friction limit v^2 / R <= g mu sets the speed (Eq. 8), and the
// steering torque limit slows the robot where the curvature changes (entering the arc).
TEST(VelocityProfile, CurvesAreTakenAtTheFrictionLimit) {
  std::vector<Point2> path{{-3, 0}};
  for (int i = 0; i <= 300; ++i) {
    const double a = -M_PI / 2 + M_PI * i / 300.0;  // a half circle of radius 1 around (0, 1)
    path.emplace_back(std::cos(a), 1.0 + std::sin(a));
  }
  path.front() = {-3, 0};
  path.insert(path.begin() + 1, Point2(0, 0));
  VelocityLimits l;
  l.max_speed = 0.8;
  l.friction = 0.02;  // sqrt(9.81 * 0.02 * 1) = 0.443 m/s on the circle
  l.max_angular_acceleration = 100.0;
  const VelocityProfile p = TimeOptimalProfile(path, l);
  const double friction_speed = std::sqrt(9.81 * 0.02 * 1.0);
  double on_arc_max = 0.0, before_arc = 0.0;
  for (size_t i = 0; i < p.points.size(); ++i) {
    if (p.points[i].x() > 0.2 && p.points[i].y() > 0.5 && p.points[i].y() < 1.5)
      on_arc_max = std::max(on_arc_max, p.speed[i]);
    if (p.points[i].x() < -1.5) before_arc = std::max(before_arc, p.speed[i]);
  }
  EXPECT_NEAR(on_arc_max, friction_speed, 0.02 * friction_speed);
  EXPECT_GT(before_arc, 0.6);  // faster on the straight
  EXPECT_DOUBLE_EQ(p.speed.back(), 0.0);
  // A weak steering torque slows the entry into the arc, where the curvature jumps from 0 to 1/m.
  l.max_angular_acceleration = 0.05;
  const VelocityProfile slow = TimeOptimalProfile(path, l);
  EXPECT_GT(slow.duration, p.duration);
}

TEST(VelocityProfile, BadLimitsAreNamed) {
  VelocityLimits l;
  l.max_acceleration = -1;
  try {
    TimeOptimalProfile({{0, 0}, {1, 0}}, l);
    FAIL() << "a negative acceleration was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("max_acceleration"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace navd::planning
