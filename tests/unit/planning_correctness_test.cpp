// Planner correctness: MovingAI scenarios (optimal lengths), and property tests on random maps
// (collision-free, right endpoints, unreachable goals reported, Theta* no longer than A*).
#include <gtest/gtest.h>

#include <filesystem>
#include <queue>
#include <random>

#include "services/common/distance_field.h"
#include "services/common/error.h"
#include "services/common/map_store.h"
#include "services/common/movingai_format.h"
#include "services/common/world.h"
#include "services/planning/dstar_lite.h"
#include "services/planning/grid_astar_planner.h"
#include "services/planning/jump_point_planner.h"
#include "services/planning/planner_catalog.h"
#include "services/planning/scenario_benchmark.h"
#include "services/planning/theta_star_planner.h"
#include "services/planning/voronoi_fast_marching_planner.h"
#include "tests/support/corridor_maze.h"

namespace navd::planning {
namespace {

// A copy of ../shared/data/movingai/arena.map(.scen) (Dragon Age: Origins, 160 scenarios).
std::string MovingAiData() { return std::string(NAVD_SOURCE_DIR) + "/tests/data/movingai"; }

TEST(MovingAi, ParsesMapsAndScenarios) {
  const OccupancyGrid g = ParseMovingAiMap("type octile\nheight 2\nwidth 3\nmap\n.T.\n@.G\n", "t.map");
  EXPECT_EQ(g.width(), 3);
  EXPECT_EQ(g.height(), 2);
  EXPECT_DOUBLE_EQ(g.resolution(), 1.0);
  EXPECT_TRUE(g.IsOccupied({1, 1}));   // 'T' on the top row
  EXPECT_TRUE(g.IsOccupied({0, 0}));   // '@' on the bottom row
  EXPECT_FALSE(g.IsOccupied({2, 0}));  // 'G' is passable
  EXPECT_EQ(MovingAiCellCenter(g, 1, 0), Point2(1.5, 1.5));
  try {
    ParseMovingAiMap("type octile\nheight 2\nwidth 3\nmap\n.T.\n@.\n", "bad.map");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.map:6"), std::string::npos) << e.what();
  }
  // Sides whose product overflows (found by the MovingAI fuzzer) are refused, not multiplied.
  EXPECT_THROW(ParseMovingAiMap("type octile\nheight 497777777777777777\nwidth 49\nmap\n", "huge.map"), Error);
}

class ScenarioTest : public ::testing::TestWithParam<std::string> {};

TEST_P(ScenarioTest, ArenaScenariosAreSolvedOptimally) {
  const std::string map = MovingAiData() + "/arena.map";
  ASSERT_TRUE(std::filesystem::exists(map)) << "test data missing: " << map;
  MapStore maps;
  const auto snapshot = maps.Set(LoadMovingAiMap(map), "arena");
  PlanningEngineOptions options;
  options.costmap.inflation_radius = 0.0;
  PlanningEngine engine(maps, options);
  RegisterDefaultPlanners(engine);
  const auto scenarios = LoadMovingAiScenarios(map + ".scen");
  const ScenarioReport r = RunScenarios(engine, snapshot->grid, scenarios, GetParam());
  EXPECT_EQ(r.passed, r.total) << r.Summary();
  for (const auto& m : r.mismatches)
    ADD_FAILURE() << "scenario " << m.index << ": expected " << m.expected << " got " << m.actual << " " << m.error;
  EXPECT_EQ(r.total, 160u);
}

INSTANTIATE_TEST_SUITE_P(Planners, ScenarioTest,
                         ::testing::Values("astar", "dijkstra", "jps", "thetastar", "dstar_lite", "distance_transform",
                                           "path_transform"));

// Random maps: obstacles as random rectangles on a 60 x 60 grid of 0.1 m cells.
std::shared_ptr<const MapSnapshot> RandomMap(MapStore& maps, std::mt19937& rng) {
  OccupancyGrid g(60, 60, 0.1, Point2::Zero());
  std::uniform_real_distribution<double> pos(0.0, 6.0), size(0.1, 1.5);
  for (int i = 0; i < 25; ++i) {
    const Point2 a(pos(rng), pos(rng));
    g.FillBox(a, a + Point2(size(rng), size(rng)));
  }
  return maps.Set(std::move(g), "random");
}

// Cells reachable from `start` by the 8-connected no-corner-cutting rule on the costmap.
std::vector<uint8_t> Reachable(const Costmap& cm, CellIndex start) {
  std::vector<uint8_t> seen(cm.grid().cells().size(), 0);
  std::queue<CellIndex> q;
  q.push(start);
  seen[cm.grid().Flat(start)] = 1;
  auto free = [&](int x, int y) { return cm.grid().Contains({x, y}) && !cm.IsLethal({x, y}); };
  while (!q.empty()) {
    const CellIndex c = q.front();
    q.pop();
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy) {
        const CellIndex n{c.x + dx, c.y + dy};
        if ((dx == 0 && dy == 0) || !free(n.x, n.y) || seen[cm.grid().Flat(n)]) continue;
        if (dx != 0 && dy != 0 && (!free(c.x + dx, c.y) || !free(c.x, c.y + dy))) continue;
        seen[cm.grid().Flat(n)] = 1;
        q.push(n);
      }
  }
  return seen;
}

TEST(PlannerProperties, RandomMapsCollisionFreeEndpointsAndUnreachable) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pos(0.05, 5.95);
  int planned = 0, unreachable = 0, contracted_planned = 0;
  for (int m = 0; m < 30; ++m) {
    MapStore maps;
    RandomMap(maps, rng);
    PlanningEngine engine(
        maps, {.costmap = {0.15, true}, .default_planner = "astar", .start_recovery_radius = 0.5, .velocity = {}});
    RegisterDefaultPlanners(engine);
    const auto cm = engine.CurrentCostmap();
    for (int q = 0; q < 10; ++q) {
      const Point2 s(pos(rng), pos(rng)), g(pos(rng), pos(rng));
      const CellIndex sc = cm->grid().CellOf(s), gc = cm->grid().CellOf(g);
      if (cm->IsLethal(sc) || cm->IsLethal(gc)) continue;
      const bool reachable = Reachable(*cm, sc)[cm->grid().Flat(gc)] != 0;
      double astar_length = -1;
      for (const std::string planner : {"astar", "dijkstra", "jps", "thetastar", "dstar_lite", "distance_transform",
                                        "path_transform", "convex_grid", "meadow_map", "topological"}) {
        for (const double smooth : {0.0, 1.0}) {
          std::map<std::string, double> options{{"smooth", smooth}};
          // The convex-cell planners search a contracted map (obstacles grown by a square, not a
          // disc), which may close gaps the costmap leaves open: they may miss a reachable goal,
          // never reach an unreachable one.
          const bool contracted = planner == "convex_grid" || planner == "meadow_map" || planner == "topological";
          try {
            const PathPlan p = engine.ComputePath(s, g, planner, options);
            EXPECT_TRUE(reachable) << planner << " found a path to an unreachable goal";
            EXPECT_EQ(p.points.front(), s);
            EXPECT_EQ(p.points.back(), g);
            for (size_t i = 1; i < p.points.size(); ++i)
              EXPECT_TRUE(cm->SegmentFree(p.points[i - 1], p.points[i]))
                  << planner << " smooth " << smooth << " segment " << i << " of " << p.points.size() - 1 << ": "
                  << FormatPoint(p.points[i - 1]) << " -> " << FormatPoint(p.points[i]);
            if (planner == "astar" && smooth == 0.0) astar_length = p.length;
            if (planner == "thetastar" && smooth == 0.0) {
              EXPECT_LE(p.length, astar_length + 1e-9);
            }
            ++planned;
            contracted_planned += contracted;
          } catch (const Error& e) {
            if (!contracted) {
              EXPECT_FALSE(reachable) << planner << ": " << e.what();
            }
            EXPECT_EQ(e.code(), ErrorCode::kNotFound);
            ++unreachable;
          }
        }
      }
    }
  }
  EXPECT_GT(planned, 500);
  EXPECT_GT(contracted_planned, 150);
  EXPECT_GT(unreachable, 0);  // the random maps do wall some goals off
}

// Points every `spacing` metres along a polyline.
std::vector<Point2> DensifyPolyline(const std::vector<Point2>& path, double spacing) {
  std::vector<Point2> out;
  for (size_t i = 1; i < path.size(); ++i) {
    const int n = std::max(1, static_cast<int>((path[i] - path[i - 1]).norm() / spacing));
    for (int k = 0; k < n; ++k) out.emplace_back(path[i - 1] + (path[i] - path[i - 1]) * (double(k) / n));
  }
  out.push_back(path.back());
  return out;
}

double CellPathCost(const std::vector<CellIndex>& cells) {
  double c = 0;
  for (size_t i = 1; i < cells.size(); ++i)
    c += (cells[i].x != cells[i - 1].x && cells[i].y != cells[i - 1].y) ? M_SQRT2 : 1.0;
  return c;
}

std::string FormatCell(const CellIndex& c) { return "(" + std::to_string(c.x) + ", " + std::to_string(c.y) + ")"; }

// A cell path is a chain of allowed grid moves: each step to a non-lethal 8-neighbour, a diagonal
// only when both side cells are free too. Returns its length in cells, or -1 when a step is not.
double GridPathLength(const Costmap& cm, const std::vector<CellIndex>& cells) {
  auto free = [&](int x, int y) { return cm.grid().Contains({x, y}) && !cm.IsLethal({x, y}); };
  double length = 0.0;
  for (size_t i = 1; i < cells.size(); ++i) {
    const int dx = cells[i].x - cells[i - 1].x, dy = cells[i].y - cells[i - 1].y;
    if (std::abs(dx) > 1 || std::abs(dy) > 1 || (dx == 0 && dy == 0) || !free(cells[i].x, cells[i].y)) return -1;
    if (dx != 0 && dy != 0 &&
        (!free(cells[i - 1].x + dx, cells[i - 1].y) || !free(cells[i - 1].x, cells[i - 1].y + dy)))
      return -1;
    length += dx != 0 && dy != 0 ? M_SQRT2 : 1.0;
  }
  return length;
}

// Jump Point Search is exact: on random grids of every density (scattered cells and boxes), and
// on wide-corridor mazes, it finds a path exactly when A* does, a valid chain of grid moves from
// start to goal, exactly as long as A*'s, with fewer expansions.
TEST(JumpPointSearch, MatchesAStarOnRandomGridsAndMazes) {
  std::mt19937 rng(47);
  const PlannerOptions astar_options{{"diagonal", 1.0}, {"cost_weight", 0.0}};
  int compared = 0, unreachable = 0;
  uint64_t jps_expansions = 0, astar_expansions = 0;
  auto compare = [&](const Costmap& cm, const CellIndex& a, const CellIndex& b) {
    const CellPath reference = GridAStarPlanner(false).Plan(cm, a, b, astar_options, {});
    const CellPath jps = JumpPointPlanner().Plan(cm, a, b, {}, {});
    ASSERT_EQ(jps.cells.empty(), reference.cells.empty()) << FormatCell(a) << " -> " << FormatCell(b);
    if (reference.cells.empty()) {
      ++unreachable;
      return;
    }
    ASSERT_EQ(jps.cells.front(), a);
    ASSERT_EQ(jps.cells.back(), b);
    const double length = GridPathLength(cm, jps.cells);
    ASSERT_GE(length, 0.0) << "not a chain of allowed moves: " << FormatCell(a) << " -> " << FormatCell(b);
    ASSERT_NEAR(length, GridPathLength(cm, reference.cells), 1e-9) << FormatCell(a) << " -> " << FormatCell(b);
    jps_expansions += jps.expansions;
    astar_expansions += reference.expansions;
    ++compared;
  };
  for (int m = 0; m < 80; ++m) {
    const int w = std::uniform_int_distribution<int>(8, 70)(rng), h = std::uniform_int_distribution<int>(8, 70)(rng);
    auto grid = std::make_shared<OccupancyGrid>(w, h, 1.0, Point2::Zero());
    const double density = std::uniform_real_distribution<double>(0.0, 0.45)(rng);
    std::uniform_int_distribution<int> x(0, w - 1), y(0, h - 1);
    for (int i = 0; i < density * w * h; ++i) grid->set({x(rng), y(rng)}, OccupancyGrid::kOccupied);
    for (int i = 0; i < m % 6; ++i) {
      const Point2 c(x(rng), y(rng));
      grid->FillBox(c, c + Point2(std::uniform_int_distribution<int>(1, 12)(rng),
                                  std::uniform_int_distribution<int>(1, 12)(rng)));
    }
    const Costmap cm(grid, {0.0, true});
    for (int q = 0; q < 40; ++q) {
      const CellIndex a{x(rng), y(rng)}, b{x(rng), y(rng)};
      if (!cm.IsLethal(a) && !cm.IsLethal(b)) compare(cm, a, b);
    }
  }
  for (const int corridor : {1, 4, 32}) {
    const Costmap cm(std::make_shared<OccupancyGrid>(testing::CorridorMaze(128, corridor, corridor)), {0.0, true});
    std::uniform_int_distribution<int> c(0, 127);
    for (int q = 0; q < 60;) {
      const CellIndex a{c(rng), c(rng)}, b{c(rng), c(rng)};
      if (cm.IsLethal(a) || cm.IsLethal(b)) continue;
      compare(cm, a, b);
      ++q;
    }
  }
  EXPECT_GT(compared, 1500);
  EXPECT_GT(unreachable, 50);
  EXPECT_LT(jps_expansions, astar_expansions / 4);
}

// After random cell changes and robot moves, D* Lite's repaired plan costs exactly what a fresh A*
// on the changed map costs, and it is a valid path on that map.
TEST(DStarLite, ReplanningMatchesPlanningFromScratch) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    auto grid = std::make_shared<OccupancyGrid>(40, 40, 1.0, Point2::Zero());
    std::uniform_int_distribution<int> coord(0, 39);
    for (int i = 0; i < 250; ++i) grid->set({coord(rng), coord(rng)}, OccupancyGrid::kOccupied);
    CellIndex start{0, 0}, goal{39, 39};
    grid->set(start, OccupancyGrid::kFree);
    grid->set(goal, OccupancyGrid::kFree);
    DStarLite dstar(Costmap(grid, {0.0, true}), start, goal);
    dstar.ComputeShortestPath();
    for (int round = 0; round < 5; ++round) {
      // Move the robot a few steps along its path, then change 16 cells (1%).
      const auto path = dstar.Path();
      if (path.size() > 4) {
        start = path[3];
        dstar.MoveStart(start);
      }
      for (int i = 0; i < 16; ++i) {
        const CellIndex c{coord(rng), coord(rng)};
        if (c == start || c == goal) continue;
        const bool block = grid->at(c) == OccupancyGrid::kFree;
        grid->set(c, block ? OccupancyGrid::kOccupied : OccupancyGrid::kFree);
        dstar.SetBlocked(c, block);
      }
      const bool found = dstar.ComputeShortestPath();
      const Costmap fresh(grid, {0.0, true});
      const CellPath astar = GridAStarPlanner().Plan(fresh, start, goal, {{"diagonal", 1.0}, {"cost_weight", 0.0}}, {});
      ASSERT_EQ(found, !astar.cells.empty()) << "trial " << trial << " round " << round;
      if (!found) break;
      const auto repaired = dstar.Path();
      ASSERT_FALSE(repaired.empty());
      EXPECT_EQ(repaired.front(), start);
      EXPECT_EQ(repaired.back(), goal);
      EXPECT_NEAR(CellPathCost(repaired), CellPathCost(astar.cells), 1e-9) << "trial " << trial << " round " << round;
      EXPECT_NEAR(dstar.PathCost(), CellPathCost(astar.cells), 1e-9);
      for (size_t i = 1; i < repaired.size(); ++i) {
        EXPECT_FALSE(fresh.IsLethal(repaired[i]));
        EXPECT_LE(std::abs(repaired[i].x - repaired[i - 1].x) + std::abs(repaired[i].y - repaired[i - 1].y), 2);
      }
    }
  }
}

TEST(DistanceField, MatchesBruteForce) {
  std::mt19937 rng(2);
  OccupancyGrid g(37, 23, 0.1, Point2::Zero());
  std::uniform_int_distribution<int> x(0, 36), y(0, 22);
  for (int i = 0; i < 30; ++i) g.set({x(rng), y(rng)}, OccupancyGrid::kOccupied);
  g.set({5, 5}, OccupancyGrid::kUnknown);
  const DistanceField field(g);
  const DistanceField with_unknown(g, true);
  for (int cy = 0; cy < 23; ++cy)
    for (int cx = 0; cx < 37; ++cx) {
      double best = INFINITY, best_u = INFINITY;
      for (int oy = 0; oy < 23; ++oy)
        for (int ox = 0; ox < 37; ++ox) {
          const double d = std::hypot(cx - ox, cy - oy) * 0.1;
          if (g.IsOccupied({ox, oy})) best = std::min(best, d);
          if (g.IsOccupied({ox, oy}) || g.at({ox, oy}) < 0) best_u = std::min(best_u, d);
        }
      ASSERT_NEAR(field.at({cx, cy}), best, 1e-9) << cx << "," << cy;
      ASSERT_NEAR(with_unknown.at({cx, cy}), best_u, 1e-9) << cx << "," << cy;
    }
  EXPECT_TRUE(std::isinf(DistanceField(OccupancyGrid(4, 4, 1.0, Point2::Zero())).at({1, 1})));
}

// The path transform trades length for clearance: through a wide room with a pillar near the
// straight line, it keeps farther from obstacles than the shortest path, and a larger alpha more so.
// With the decay layer, A* (and the shortcuts after it) keep off the walls where there is room.
TEST(CostAwareAStar, KeepsClearanceInTheWarehouse) {
  MapStore maps;
  maps.Set(DefaultWorld().map, "warehouse");
  PlanningEngine plain(
      maps, {.costmap = {0.30, true}, .default_planner = "astar", .start_recovery_radius = 0.5, .velocity = {}});
  PlanningEngine aware(
      maps,
      {.costmap = {0.30, true, 0.5, 3.0}, .default_planner = "astar", .start_recovery_radius = 0.5, .velocity = {}});
  RegisterDefaultPlanners(plain);
  RegisterDefaultPlanners(aware);
  const DistanceField field(plain.CurrentCostmap()->grid());
  auto mean_clearance = [&](const PathPlan& p) {
    const auto dense = DensifyPolyline(p.points, 0.05);
    double sum = 0;
    for (const auto& q : dense) sum += std::min(1.0, field.at(plain.CurrentCostmap()->grid().CellOf(q)));
    return sum / dense.size();
  };
  const PathPlan a = plain.ComputePath({0.8, 1.0}, {8.8, 8.8}, "astar", {});
  const PathPlan b = aware.ComputePath({0.8, 1.0}, {8.8, 8.8}, "astar", {});
  const PathPlan c = aware.ComputePath({0.8, 1.0}, {8.8, 8.8}, "astar", {{"cost_weight", 0}, {"smooth", 0}});
  const PathPlan a_raw = plain.ComputePath({0.8, 1.0}, {8.8, 8.8}, "astar", {{"smooth", 0}});
  EXPECT_GT(mean_clearance(b), mean_clearance(a) + 0.05);
  EXPECT_LT(b.length, 1.25 * a.length);
  EXPECT_NEAR(c.length, a_raw.length, 1e-9);  // weight 0: the plain shortest cell path
  for (size_t i = 1; i < b.points.size(); ++i)
    EXPECT_TRUE(aware.CurrentCostmap()->SegmentFree(b.points[i - 1], b.points[i]));
}

TEST(PathTransform, KeepsClearanceThatTheShortestPathDoesNot) {
  MapStore maps;
  OccupancyGrid g(100, 60, 0.1, Point2::Zero());
  g.FillBox({4.8, 2.6}, {5.2, 3.4});  // a pillar just above the straight line y = 2.5
  maps.Set(std::move(g), "room");
  PlanningEngine engine(
      maps, {.costmap = {0.0, true}, .default_planner = "astar", .start_recovery_radius = 0.5, .velocity = {}});
  RegisterDefaultPlanners(engine);
  const DistanceField field(engine.CurrentCostmap()->grid());
  auto min_clearance = [&](const PathPlan& p) {
    double c = INFINITY;
    for (size_t i = 1; i < p.points.size(); ++i)
      for (int k = 0; k <= 20; ++k) {
        const Point2 q = p.points[i - 1] + (p.points[i] - p.points[i - 1]) * (k / 20.0);
        c = std::min(c, field.at(engine.CurrentCostmap()->grid().CellOf(q)));
      }
    return c;
  };
  const PathPlan shortest = engine.ComputePath({1, 2.5}, {9, 2.5}, "astar", {{"smooth", 0}});
  const PathPlan careful = engine.ComputePath({1, 2.5}, {9, 2.5}, "path_transform", {{"smooth", 0}, {"alpha", 4.0}});
  EXPECT_GT(min_clearance(careful), min_clearance(shortest) + 0.2);
  EXPECT_GT(careful.length, shortest.length);
  EXPECT_LT(careful.length, shortest.length * 1.5);
}

// OMPL planners on the warehouse: collision-free (exact segment test) paths from start to goal,
// honouring the time budget and cancellation, in SE(2) and for car-like robots.
TEST(OmplPlanners, FindCollisionFreePathsInTheWarehouse) {
  MapStore maps;
  maps.Set(DefaultWorld().map, "warehouse");
  PlanningEngine engine(
      maps, {.costmap = {0.30, true}, .default_planner = "astar", .start_recovery_radius = 0.5, .velocity = {}});
  RegisterDefaultPlanners(engine);
  const auto cm = engine.CurrentCostmap();
  const Point2 s(0.8, 1.0), g(8.8, 8.8);
  const double astar = engine.ComputePath(s, g, "astar", {}).length;
  for (const std::string planner : {"rrt_connect", "rrt_star", "prm_star", "informed_rrt_star", "bit_star"}) {
    const PathPlan p = engine.ComputePath(s, g, planner, {{"time_limit", 0.2}});
    EXPECT_EQ(p.points.front(), s);
    EXPECT_EQ(p.points.back(), g);
    for (size_t i = 1; i < p.points.size(); ++i)
      EXPECT_TRUE(cm->SegmentFree(p.points[i - 1], p.points[i])) << planner << " segment " << i;
    EXPECT_LT(p.length, 1.6 * astar) << planner;
    EXPECT_LT(p.planning_time, 2.0) << planner;
  }
  // Reeds-Shepp with a turning radius: a feasible curve sampled along its length.
  const PathPlan rs = engine.ComputePath({0.8, 2.0}, {0.8, 8.0}, "rrt_connect",
                                         {{"space", 2},
                                          {"turning_radius", 0.3},
                                          {"start_yaw", M_PI / 2},
                                          {"goal_yaw", M_PI / 2}});  // smoothing must leave curves alone
  EXPECT_GT(rs.points.size(), 10u);
  EXPECT_GE(rs.length, 6.0 - 1e-6);
  // Cancellation before any solution: DEADLINE_EXCEEDED.
  try {
    engine.ComputePath(s, g, "rrt_star", {{"time_limit", 5.0}}, [] { return true; });
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kDeadlineExceeded);
  }
  try {
    engine.ComputePath(s, g, "rrt_star", {{"space", 7}});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("space"), std::string::npos);
  }
}

TEST(FastMarching, ArrivalTimesApproximateEuclideanDistance) {
  const int n = 101;
  const std::vector<double> speed(n * n, 1.0);
  const auto t = FastMarch(n, n, 0.1, speed, {50, 50});
  EXPECT_DOUBLE_EQ(t[50 * n + 50], 0.0);
  EXPECT_NEAR(t[50 * n + 100], 5.0, 1e-5);  // along an axis the scheme is exact (float times)
  // Diagonals: first-order fast marching overestimates by a few percent.
  const double diagonal = t[100 * n + 100], exact = std::hypot(5.0, 5.0);
  EXPECT_GT(diagonal, exact);
  EXPECT_LT(diagonal, exact * 1.1);
  // Half speed: twice the time.
  std::vector<double> slow(n * n, 0.5);
  EXPECT_NEAR(FastMarch(n, n, 0.1, slow, {50, 50})[50 * n + 100], 10.0, 1e-5);
}

TEST(VoronoiFastMarching, SmoothSafePathWithSpeedLimits) {
  MapStore maps;
  maps.Set(DefaultWorld().map, "warehouse");
  PlanningEngine engine(
      maps, {.costmap = {0.30, true}, .default_planner = "astar", .start_recovery_radius = 0.5, .velocity = {}});
  RegisterDefaultPlanners(engine);
  const auto cm = engine.CurrentCostmap();
  const DistanceField field(cm->grid());
  const Point2 s(0.8, 1.0), g(8.8, 8.8);
  const PathPlan vfm = engine.ComputePath(s, g, "voronoi_fast_marching", {});
  const PathPlan astar = engine.ComputePath(s, g, "astar", {});
  EXPECT_EQ(vfm.points.front(), s);
  EXPECT_EQ(vfm.points.back(), g);
  ASSERT_EQ(vfm.speed_limits.size(), vfm.points.size());
  double mean_clearance_vfm = 0, mean_clearance_astar = 0;
  for (size_t i = 0; i < vfm.points.size(); ++i) {
    if (i > 0) {
      EXPECT_TRUE(cm->SegmentFree(vfm.points[i - 1], vfm.points[i])) << i;
    }
    EXPECT_GT(vfm.speed_limits[i], 0.0);
    EXPECT_LE(vfm.speed_limits[i], 1.0);
    mean_clearance_vfm += field.at(cm->grid().CellOf(vfm.points[i])) / vfm.points.size();
  }
  const auto dense = DensifyPolyline(astar.points, 0.05);
  for (const auto& p : dense) mean_clearance_astar += field.at(cm->grid().CellOf(p)) / dense.size();
  EXPECT_GT(mean_clearance_vfm, mean_clearance_astar + 0.1);
  EXPECT_LT(vfm.length, 1.5 * astar.length);
  // Smooth: no sharp turns between consecutive steps.
  for (size_t i = 2; i + 1 < vfm.points.size(); ++i) {
    const Point2 a = vfm.points[i - 1] - vfm.points[i - 2], b = vfm.points[i] - vfm.points[i - 1];
    if (a.norm() < 1e-6 || b.norm() < 1e-6) continue;
    EXPECT_GT(a.normalized().dot(b.normalized()), std::cos(M_PI / 3)) << "turn at point " << i;
  }
}

TEST(ThetaStar, LineOfSightRespectsDiagonalCorners) {
  auto grid = std::make_shared<OccupancyGrid>(4, 4, 1.0, Point2::Zero());
  grid->set({1, 2}, OccupancyGrid::kOccupied);
  Costmap cm(grid, {0.0, true});
  EXPECT_TRUE(CellsSeeEachOther(cm, {0, 0}, {3, 0}));
  EXPECT_FALSE(CellsSeeEachOther(cm, {0, 3}, {3, 0}));  // passes through (1,2)'s corner
  grid->set({1, 2}, OccupancyGrid::kFree);
  grid->set({2, 2}, OccupancyGrid::kOccupied);
  grid->set({1, 1}, OccupancyGrid::kOccupied);
  Costmap cm2(grid, {0.0, true});
  EXPECT_FALSE(CellsSeeEachOther(cm2, {0, 0}, {3, 3}));  // squeezes between diagonal blocks
}

}  // namespace
}  // namespace navd::planning
