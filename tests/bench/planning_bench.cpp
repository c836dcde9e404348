// Planning speed on the embedded warehouse world: costmap inflation, and A* vs Dijkstra between
// the demo's start and goals. Run: build/tests/planning_bench
#include <benchmark/benchmark.h>

#include "services/common/map_store.h"
#include "services/common/world.h"
#include "services/planning/grid_astar_planner.h"
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
  engine.Register(std::make_unique<planning::GridAStarPlanner>(false));
  engine.Register(std::make_unique<planning::GridAStarPlanner>(true));
  engine.CurrentCostmap();
  const Point2 start = Warehouse().start.translation();
  const Point2 goal = Warehouse().goals[0].translation();  // across the arena
  uint64_t expansions = 0;
  for (auto _ : state) {
    const auto plan = engine.ComputePath(start, goal, planner, {});
    expansions = plan.expansions;
    benchmark::DoNotOptimize(plan);
  }
  state.counters["expansions"] = static_cast<double>(expansions);
}
BENCHMARK_CAPTURE(BM_Plan, astar, std::string("astar"))->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Plan, dijkstra, std::string("dijkstra"))->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
