// The planners built on the convex decomposition of free space: seed 000's convex navigation
// grid, seed 004's meadow map, book chapter 1's topological graph with its table of routes.
#include <gtest/gtest.h>

#include "services/common/error.h"
#include "services/common/map_store.h"
#include "services/common/world.h"
#include "services/planning/convex_grid_planner.h"
#include "services/planning/meadow_map_planner.h"
#include "services/planning/planner_catalog.h"
#include "services/planning/topological_graph_planner.h"

namespace navd::planning {
namespace {

std::shared_ptr<const Costmap> WarehouseCostmap() {
  static const auto costmap = std::make_shared<const Costmap>(std::make_shared<const OccupancyGrid>(DefaultWorld().map),
                                                              CostmapOptions{0.30, true});
  return costmap;
}

void ExpectCollisionFree(const Costmap& cm, const std::vector<Point2>& points, const std::string& what) {
  for (size_t i = 1; i < points.size(); ++i)
    EXPECT_TRUE(cm.SegmentFree(points[i - 1], points[i])) << what << " leg " << i;
}

TEST(ConvexCellMap, CellsAreDisjointRectanglesCoveringTheContractedFreeSpace) {
  const Costmap& cm = *WarehouseCostmap();
  const double margin = 0.05;
  const ConvexCellMap cells(cm, margin);
  const OccupancyGrid& g = cm.grid();
  // The contracted map by brute force: no obstacle within k cells in x and in y.
  const int k = static_cast<int>(std::ceil((cm.options().inflation_radius + margin) / g.resolution() - 1e-9));
  std::vector<uint8_t> contracted(g.cells().size(), 0);
  for (int y = 0; y < g.height(); ++y) {
    for (int x = 0; x < g.width(); ++x) {
      bool clear = !cm.IsLethal({x, y});
      for (int dy = -k; dy <= k && clear; ++dy)
        for (int dx = -k; dx <= k && clear; ++dx)
          if (g.Contains({x + dx, y + dy}) && g.IsOccupied({x + dx, y + dy})) clear = false;
      contracted[g.Flat({x, y})] = clear;
    }
  }
  // Every contracted-free raster cell lies in exactly one convex cell, every other in none.
  size_t free_cells = 0;
  std::vector<int> covered(g.cells().size(), 0);
  for (const ConvexCell& c : cells.cells()) {
    const CellIndex lo = g.CellOf(c.min + Point2(1e-9, 1e-9)), hi = g.CellOf(c.max - Point2(1e-9, 1e-9));
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) ++covered[g.Flat({x, y})];
  }
  for (size_t i = 0; i < covered.size(); ++i) {
    const bool contracted_free = contracted[i];
    free_cells += contracted_free;
    ASSERT_EQ(covered[i], contracted_free ? 1 : 0) << "raster cell " << i;
  }
  // Joining leaves far fewer cells than raster cells, and every doorway is a side two cells share.
  EXPECT_LT(cells.cells().size() * 20, free_cells);
  EXPECT_FALSE(cells.doorways().empty());
  for (const Doorway& d : cells.doorways()) {
    EXPECT_GT(Distance(d.a, d.b), 0.0);
    const ConvexCell &p = cells.cells()[d.cells[0]], &q = cells.cells()[d.cells[1]];
    for (const Point2& e : {d.a, d.b})
      for (const ConvexCell* c : {&p, &q})
        EXPECT_TRUE(e.x() >= c->min.x() - 1e-9 && e.x() <= c->max.x() + 1e-9 && e.y() >= c->min.y() - 1e-9 &&
                    e.y() <= c->max.y() + 1e-9);
  }
  EXPECT_THROW(ConvexCellMap(cm, -0.1), Error);
}

// A 10 x 6 m room with a 2 x 2 m block in the middle: two ways from left to right.
std::shared_ptr<const Costmap> RoomWithBlock() {
  static const auto costmap = [] {
    OccupancyGrid g(200, 120, 0.05, Point2::Zero());
    g.FillBox({0.0, 0.0}, {10.0, 0.1});
    g.FillBox({0.0, 5.9}, {10.0, 6.0});
    g.FillBox({0.0, 0.0}, {0.1, 6.0});
    g.FillBox({9.9, 0.0}, {10.0, 6.0});
    g.FillBox({4.0, 2.0}, {6.0, 4.0});
    return std::make_shared<const Costmap>(std::make_shared<const OccupancyGrid>(std::move(g)),
                                           CostmapOptions{0.30, true});
  }();
  return costmap;
}

TEST(ConvexGrid, IteratingShortensThePathAndAMovingObstacleChangesTheRoute) {
  const Costmap& cm = *RoomWithBlock();
  const ConvexCellMap cells(cm, 0.05);
  const Point2 start(1.0, 3.0), goal(9.0, 3.0);
  ConvexGridOptions o;
  o.iterations = 30;
  o.waypoint_spacing = 0.4;
  const ConvexGridPath free_run = PlanOnConvexGrid(cells, cm, start, goal, o);
  // Seed 000 Fig. 6: the best path so far only gets shorter, and later tries beat the first.
  ASSERT_EQ(free_run.best_length_per_iteration.size(), 30u);
  for (size_t i = 1; i < free_run.best_length_per_iteration.size(); ++i)
    EXPECT_LE(free_run.best_length_per_iteration[i], free_run.best_length_per_iteration[i - 1]);
  EXPECT_LT(free_run.best_length_per_iteration.back(), free_run.best_length_per_iteration.front());
  EXPECT_EQ(free_run.points.front(), start);
  EXPECT_EQ(free_run.points.back(), goal);
  ExpectCollisionFree(cm, free_run.points, "free run");
  for (size_t i = 1; i < free_run.points.size(); ++i)
    EXPECT_LE(Distance(free_run.points[i - 1], free_run.points[i]), o.waypoint_spacing + 1e-9);
  EXPECT_LT(free_run.length, 1.25 * Distance(start, goal));
  auto side_of_block = [](const ConvexGridPath& p) {  // +1 above the block, -1 below
    for (const Point2& q : p.points)
      if (std::abs(q.x() - 5.0) < 0.3) return q.y() > 3.0 ? 1 : -1;
    return 0;
  };
  const int side = side_of_block(free_run);
  ASSERT_NE(side, 0);

  // Seed 000 Fig. 7: a moving obstacle on that side, within Δ of the robot: the route takes the other.
  const MovingObstacleCircle obstacle{{3.5, 3.0 + side * 1.6}, 0.3};
  ASSERT_LT(Distance(obstacle.centre, start), o.obstacle_range);
  const ConvexGridPath avoiding = PlanOnConvexGrid(cells, cm, start, goal, o, {obstacle});
  EXPECT_FALSE(avoiding.penalised);
  EXPECT_EQ(side_of_block(avoiding), -side);
  for (size_t i = 1; i < avoiding.points.size(); ++i)
    EXPECT_GT(DistanceToSegment(obstacle.centre, avoiding.points[i - 1], avoiding.points[i]),
              obstacle.radius + o.obstacle_margin);
  ExpectCollisionFree(cm, avoiding.points, "avoiding");
  // The same obstacle farther than Δ is ignored.
  o.obstacle_range = 0.5 * Distance(obstacle.centre, start);
  EXPECT_NEAR(PlanOnConvexGrid(cells, cm, start, goal, o, {obstacle}).length, free_run.length, 1e-9);
}

TEST(ConvexGrid, StartInTheMarginJoinsTheGridAndFarPointsAreRefused) {
  const Costmap& cm = *RoomWithBlock();
  const ConvexCellMap cells(cm, 0.3);  // a wide margin: a start near the wall sits in it
  const Point2 start(0.5, 3.0);
  ASSERT_FALSE(cm.IsLethal(cm.grid().CellOf(start)));
  ASSERT_LT(cells.CellAt(start), 0);
  const ConvexGridPath p = PlanOnConvexGrid(cells, cm, start, {9.0, 3.0}, {});
  EXPECT_EQ(p.points.front(), start);
  ExpectCollisionFree(cm, p.points, "from the margin");
  ConvexGridOptions tight;
  tight.entry_reach = 0.1;
  try {
    PlanOnConvexGrid(cells, cm, start, {9.0, 3.0}, tight);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNotFound);
    EXPECT_NE(std::string(e.what()).find("start"), std::string::npos) << e.what();
  }
}

TEST(MeadowMap, AStarOverBorderMidpointsIsCollisionFreeAndNearTheShortest) {
  MapStore maps;
  maps.Set(DefaultWorld().map, "warehouse");
  PlanningEngine engine(
      maps, {.costmap = {0.30, true}, .default_planner = "astar", .start_recovery_radius = 0.5, .velocity = {}});
  RegisterDefaultPlanners(engine);
  const auto cm = engine.CurrentCostmap();
  const Point2 s(0.8, 1.0), g(8.8, 8.8);
  const double astar = engine.ComputePath(s, g, "astar", {}).length;
  for (const double smooth : {0.0, 1.0}) {
    const PathPlan p = engine.ComputePath(s, g, "meadow_map", {{"smooth", smooth}});
    EXPECT_EQ(p.planner, "meadow_map");
    EXPECT_GT(p.expansions, 0u);
    ExpectCollisionFree(*cm, p.points, "meadow map");
    EXPECT_LT(p.length, 1.35 * astar) << "smooth " << smooth;
    EXPECT_GE(p.length, astar * 0.9);
  }
  // Start and goal in one meadow: one straight leg.
  const PathPlan same = engine.ComputePath({0.8, 1.0}, {0.9, 1.1}, "meadow_map", {{"smooth", 0.0}});
  EXPECT_EQ(same.points.size(), 2u);
}

TEST(TopologicalGraph, RoutesComeFromTheTableAfterTheFirstQueryFromAPlace) {
  MapStore maps;
  maps.Set(DefaultWorld().map, "warehouse");
  PlanningEngine engine(
      maps, {.costmap = {0.30, true}, .default_planner = "astar", .start_recovery_radius = 0.5, .velocity = {}});
  auto cells = std::make_shared<ConvexCellMapCache>();
  auto owned = std::make_unique<TopologicalGraphPlanner>(cells);
  const TopologicalGraphPlanner& topo = *owned;
  engine.Register(std::move(owned));
  const auto cm = engine.CurrentCostmap();
  const PathPlan first = engine.ComputePath({0.8, 1.0}, {8.8, 8.8}, "topological", {});
  EXPECT_GT(first.expansions, 0u);
  EXPECT_EQ(topo.table_misses(), 1u);
  ExpectCollisionFree(*cm, first.points, "first");
  // Same place, another goal: the tree from that place is in the table.
  const PathPlan second = engine.ComputePath({0.8, 1.0}, {1.0, 8.8}, "topological", {});
  EXPECT_EQ(second.expansions, 0u);
  EXPECT_EQ(topo.table_hits(), 1u);
  ExpectCollisionFree(*cm, second.points, "second");
  const PathPlan again = engine.ComputePath({0.8, 1.0}, {8.8, 8.8}, "topological", {});
  EXPECT_EQ(again.points, first.points);
  // A new map empties the table.
  OccupancyGrid changed = DefaultWorld().map;
  maps.Set(std::move(changed), "warehouse again");
  engine.ComputePath({0.8, 1.0}, {8.8, 8.8}, "topological", {});
  EXPECT_EQ(topo.table_misses(), 2u);
}

}  // namespace
}  // namespace navd::planning
