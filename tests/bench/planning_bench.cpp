// Planning speed on the embedded warehouse world: costmap inflation, and A* vs Dijkstra between
// the demo's start and goals. Run: build/tests/planning_bench
#include <benchmark/benchmark.h>

#include "services/common/map_store.h"
#include "services/common/world.h"
#include <random>

#include "services/common/distance_field.h"

#include "services/planning/dstar_lite.h"
#include "services/planning/grid_astar_planner.h"
#include "services/planning/planner_catalog.h"
#include "services/planning/theta_star_planner.h"
#include "services/planning/voronoi_fast_marching_planner.h"
#include "services/planning/planning_engine.h"

namespace {

using namespace navd;

const World& Warehouse() {
  static const World w = DefaultWorld();
  return w;
}

void BM_CostmapInflation(benchmark::State& state) {
  auto grid = std::make_shared<OccupancyGrid>(Warehouse().map);
  for (auto _ : state) benchmark::DoNotOptimize(planning::Costmap(grid, {0.30, true}));
}
BENCHMARK(BM_CostmapInflation)->Unit(benchmark::kMicrosecond);

void BM_Plan(benchmark::State& state, const std::string& planner) {
  MapStore maps;
  maps.Set(Warehouse().map, "warehouse");
  planning::PlanningEngine engine(maps, {{0.30, true}, "astar", 0.5});
  planning::RegisterDefaultPlanners(engine);
  engine.CurrentCostmap();
  const Point2 start = Warehouse().start.translation();
  const Point2 goal = Warehouse().goals[0].translation();  // across the arena
  uint64_t expansions = 0;
  for (auto _ : state) {
    const bool raw = planner.size() > 4 && planner.substr(planner.size() - 4) == ":raw";
    const auto plan = engine.ComputePath(start, goal, raw ? planner.substr(0, planner.size() - 4) : planner,
                                         {{"smooth", raw ? 0.0 : 1.0}});
    expansions = plan.expansions;
    benchmark::DoNotOptimize(plan);
  }
  state.counters["expansions"] = static_cast<double>(expansions);
}
BENCHMARK_CAPTURE(BM_Plan, astar, std::string("astar"))->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Plan, astar_unsmoothed, std::string("astar:raw"))->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Plan, dijkstra, std::string("dijkstra"))->Unit(benchmark::kMicrosecond);

// A 512 x 512 maze of 1-cell corridors (depth-first carving, fixed seed): the hardest kind of map
// for grid search, as in the MovingAI maze set.
std::shared_ptr<const OccupancyGrid> Maze512() {
  static const auto maze = [] {
    auto g = std::make_shared<OccupancyGrid>(512, 512, 1.0, Point2::Zero(), OccupancyGrid::kOccupied);
    std::mt19937 rng(3);
    const int n = 255;  // maze nodes per side, at odd coordinates 1..509
    std::vector<uint8_t> seen(n * n, 0);
    std::vector<std::pair<int, int>> stack{{0, 0}};
    seen[0] = 1;
    g->set({1, 1}, OccupancyGrid::kFree);
    while (!stack.empty()) {
      auto [x, y] = stack.back();
      std::vector<std::pair<int, int>> next;
      for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int nx = x + dx, ny = y + dy;
        if (nx >= 0 && ny >= 0 && nx < n && ny < n && !seen[ny * n + nx]) next.push_back({nx, ny});
      }
      if (next.empty()) {
        stack.pop_back();
        continue;
      }
      auto [nx, ny] = next[rng() % next.size()];
      seen[ny * n + nx] = 1;
      g->set({2 * nx + 1, 2 * ny + 1}, OccupancyGrid::kFree);
      g->set({x + nx + 1, y + ny + 1}, OccupancyGrid::kFree);
      stack.push_back({nx, ny});
    }
    return g;
  }();
  return maze;
}

// Raw search speed: expansions per second of the planner alone, corner to corner of the maze.
void BM_MazeSearch(benchmark::State& state, const std::string& name) {
  planning::Costmap costmap(Maze512(), {0.0, true});
  std::unique_ptr<planning::GlobalPlanner> planner;
  if (name == "thetastar") planner = std::make_unique<planning::ThetaStarPlanner>();
  else planner = std::make_unique<planning::GridAStarPlanner>(name == "dijkstra");
  uint64_t expansions = 0;
  for (auto _ : state) {
    const auto path = planner->Plan(costmap, {1, 1}, {509, 509}, {{"diagonal", 1.0}, {"cost_weight", 0.0}, {"smooth", 0.0}}, {});
    expansions += path.expansions;
    benchmark::DoNotOptimize(path);
  }
  state.counters["expansions_per_s"] = benchmark::Counter(static_cast<double>(expansions), benchmark::Counter::kIsRate);
}
BENCHMARK_CAPTURE(BM_MazeSearch, astar, std::string("astar"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MazeSearch, dijkstra, std::string("dijkstra"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MazeSearch, thetastar, std::string("thetastar"))->Unit(benchmark::kMillisecond);

// Seed 002's comparison of A* and D*: plan on a 512 x 512 map with 20% random obstacles, then 1%
// of the cells change (random toggles) and the plan is repaired. Reports time and states
// processed (expansions) for D* Lite's repair against A* planning again from scratch.
// Two kinds of change: `local` puts all changed cells within 60 cells of the robot (what its
// sensors discover as it drives, the case D* Lite is built for); otherwise they are spread over
// the whole map.
struct ReplanCase {
  std::shared_ptr<OccupancyGrid> before, after;
  std::vector<std::pair<CellIndex, bool>> changes;
  CellIndex start{0, 0}, goal{511, 511};
};

ReplanCase MakeReplanCase(bool local) {
  ReplanCase rc;
  {
    rc.before = std::make_shared<OccupancyGrid>(512, 512, 1.0, Point2::Zero());
    std::mt19937 rng(9);
    std::uniform_int_distribution<int> coord(0, 511);
    for (int i = 0; i < 512 * 512 / 5; ++i) rc.before->set({coord(rng), coord(rng)}, OccupancyGrid::kOccupied);
    rc.before->set({0, 0}, OccupancyGrid::kFree);
    rc.before->set({511, 511}, OccupancyGrid::kFree);
    rc.after = std::make_shared<OccupancyGrid>(*rc.before);
    if (local) {
      rc.start = {128, 128};
      rc.before->set(rc.start, OccupancyGrid::kFree);
      rc.after->set(rc.start, OccupancyGrid::kFree);
    }
    std::uniform_int_distribution<int> near(-60, 60);
    std::vector<uint8_t> changed(512 * 512, 0);
    while (rc.changes.size() < 512 * 512 / 100) {
      const CellIndex cell = local ? CellIndex{rc.start.x + near(rng), rc.start.y + near(rng)}
                                   : CellIndex{coord(rng), coord(rng)};
      if (!rc.after->Contains(cell) || cell == rc.start || cell == rc.goal || changed[rc.after->Flat(cell)]) continue;
      if (local && std::hypot(cell.x - rc.start.x, cell.y - rc.start.y) > 60) continue;
      changed[rc.after->Flat(cell)] = 1;
      const bool block = rc.after->at(cell) == OccupancyGrid::kFree;
      rc.after->set(cell, block ? OccupancyGrid::kOccupied : OccupancyGrid::kFree);
      rc.changes.push_back({cell, block});
    }
  }
  return rc;
}

const ReplanCase& Replan512(bool local) {
  static const ReplanCase spread = MakeReplanCase(false), near = MakeReplanCase(true);
  return local ? near : spread;
}

void BM_Replan_AStarFromScratch(benchmark::State& state, bool local) {
  const ReplanCase& rc = Replan512(local);
  planning::Costmap after(rc.after, {0.0, true});
  uint64_t expansions = 0;
  for (auto _ : state) {
    const auto p = planning::GridAStarPlanner().Plan(after, rc.start, rc.goal, {{"diagonal", 1.0}, {"cost_weight", 0.0}}, {});
    expansions = p.expansions;
    benchmark::DoNotOptimize(p);
  }
  state.counters["states_processed"] = static_cast<double>(expansions);
}
BENCHMARK_CAPTURE(BM_Replan_AStarFromScratch, spread, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Replan_AStarFromScratch, local, true)->Unit(benchmark::kMillisecond);

void BM_Replan_DStarLiteInitial(benchmark::State& state, bool local) {
  const ReplanCase& rc = Replan512(local);
  planning::Costmap before(rc.before, {0.0, true});
  uint64_t expansions = 0;
  for (auto _ : state) {
    planning::DStarLite dstar(before, rc.start, rc.goal);
    dstar.ComputeShortestPath();
    expansions = dstar.expansions();
    benchmark::DoNotOptimize(dstar);
  }
  state.counters["states_processed"] = static_cast<double>(expansions);
}
BENCHMARK_CAPTURE(BM_Replan_DStarLiteInitial, spread, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Replan_DStarLiteInitial, local, true)->Unit(benchmark::kMillisecond);

void BM_Replan_DStarLiteRepair(benchmark::State& state, bool local) {
  const ReplanCase& rc = Replan512(local);
  planning::Costmap before(rc.before, {0.0, true});
  uint64_t expansions = 0;
  for (auto _ : state) {
    state.PauseTiming();
    auto dstar = std::make_unique<planning::DStarLite>(before, rc.start, rc.goal);
    dstar->ComputeShortestPath();
    const uint64_t initial = dstar->expansions();
    state.ResumeTiming();
    for (const auto& [cell, blocked] : rc.changes) dstar->SetBlocked(cell, blocked);
    dstar->ComputeShortestPath();
    expansions = dstar->expansions() - initial;
    state.PauseTiming();
    dstar.reset();
    state.ResumeTiming();
  }
  state.counters["states_processed"] = static_cast<double>(expansions);
}
BENCHMARK_CAPTURE(BM_Replan_DStarLiteRepair, spread, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Replan_DStarLiteRepair, local, true)->Unit(benchmark::kMillisecond);

// Fast Marching over a 1000 x 1000 grid (5 cm cells, a 50 x 50 m floor with 300 random boxes) on
// the speed map Voronoi Fast Marching uses (log of the distance to obstacles), front from the centre.
void BM_FastMarching1000(benchmark::State& state) {
  const int n = 1000;
  OccupancyGrid g(n, n, 0.05, Point2::Zero());
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> pos(0.0, 50.0), size(0.2, 2.5);
  for (int i = 0; i < 300; ++i) {
    const Point2 a(pos(rng), pos(rng));
    g.FillBox(a, a + Point2(size(rng), size(rng)));
  }
  g.FillBox({24.0, 24.0}, {26.0, 26.0}, OccupancyGrid::kFree);
  const DistanceField evt(g);
  std::vector<double> speed(evt.values().size());
  for (size_t i = 0; i < speed.size(); ++i)
    speed[i] = evt.values()[i] <= 0.0 ? 0.0 : std::max(0.05, std::log1p(std::min(evt.values()[i], 2.0)) / std::log1p(2.0));
  for (auto _ : state) benchmark::DoNotOptimize(planning::FastMarch(n, n, 0.05, speed, {500, 500}));
}
BENCHMARK(BM_FastMarching1000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
