// Planning speed: costmap inflation and planners on the embedded warehouse world, per-query
// times over a MovingAI-style corridor maze and arena, D* Lite's repairs, Fast Marching.
// Run: build/tests/planning_bench (--benchmark_filter=Queries for the per-query batches)
#include <benchmark/benchmark.h>

#include <random>

#include "services/common/distance_field.h"
#include "services/common/map_store.h"
#include "services/common/movingai_format.h"
#include "services/common/world.h"
#include "tests/support/corridor_maze.h"

#include "services/planning/dstar_lite.h"
#include "services/planning/grid_astar_planner.h"
#include "services/planning/planner_catalog.h"
#include "services/planning/theta_star_planner.h"
#include "services/planning/voronoi_fast_marching_planner.h"
#include "services/planning/planning_engine.h"
#include "services/planning/scenario_benchmark.h"

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

// decay: the daemon's default costmap (0.5 m of decaying cost beyond the inflation), which the
// cost-aware planners weigh; without it every step costs its length.
void BM_Plan(benchmark::State& state, const std::string& planner, double decay) {
  MapStore maps;
  maps.Set(Warehouse().map, "warehouse");
  planning::PlanningEngine engine(
      maps, {.costmap = {0.30, true, decay}, .default_planner = "astar", .start_recovery_radius = 0.5, .velocity = {}});
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
BENCHMARK_CAPTURE(BM_Plan, astar, std::string("astar"), 0.0)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Plan, astar_unsmoothed, std::string("astar:raw"), 0.0)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Plan, dijkstra, std::string("dijkstra"), 0.0)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Plan, astar_decay, std::string("astar"), 0.5)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Plan, dijkstra_decay, std::string("dijkstra"), 0.5)->Unit(benchmark::kMicrosecond);

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
        if (nx >= 0 && ny >= 0 && nx < n && ny < n && !seen[ny * n + nx]) next.emplace_back(nx, ny);
      }
      if (next.empty()) {
        stack.pop_back();
        continue;
      }
      auto [nx, ny] = next[rng() % next.size()];
      seen[ny * n + nx] = 1;
      g->set({2 * nx + 1, 2 * ny + 1}, OccupancyGrid::kFree);
      g->set({x + nx + 1, y + ny + 1}, OccupancyGrid::kFree);
      stack.emplace_back(nx, ny);
    }
    return g;
  }();
  return maze;
}

// Raw search speed: expansions per second of the planner alone, corner to corner of the maze.
void BM_MazeSearch(benchmark::State& state, const std::string& name) {
  planning::Costmap costmap(Maze512(), {0.0, true});
  std::unique_ptr<planning::GlobalPlanner> planner;
  if (name == "thetastar")
    planner = std::make_unique<planning::ThetaStarPlanner>();
  else
    planner = std::make_unique<planning::GridAStarPlanner>(name == "dijkstra");
  uint64_t expansions = 0;
  for (auto _ : state) {
    const auto path =
        planner->Plan(costmap, {1, 1}, {509, 509}, {{"diagonal", 1.0}, {"cost_weight", 0.0}, {"smooth", 0.0}}, {});
    expansions += path.expansions;
    benchmark::DoNotOptimize(path);
  }
  state.counters["expansions_per_s"] = benchmark::Counter(static_cast<double>(expansions), benchmark::Counter::kIsRate);
}
BENCHMARK_CAPTURE(BM_MazeSearch, astar, std::string("astar"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MazeSearch, dijkstra, std::string("dijkstra"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MazeSearch, thetastar, std::string("thetastar"))->Unit(benchmark::kMillisecond);

// Per-query batches, as `navctl plan --map --scen` runs them (through the planning engine, no
// smoothing): each planner plans every query once; counters give the median and p99 per query in
// ms and, on maps without a cost layer, how many paths matched the optimal length (dijkstra's on
// the maze, the file's on arena).
struct QueryBatch {
  MapStore maps;
  std::shared_ptr<const MapSnapshot> snapshot;
  std::vector<MovingAiScenario> scenarios;
  planning::CostmapOptions costmap;
};

// MovingAI's maze512-32 family: 512 x 512, 32-cell corridors; 1,000 random pairs of free cells.
// `decay`: plan on the costmap navd plans on by default, with inflation and a decaying cost beside
// walls (1 m lethal, 3 m of decay on these 1 m cells), where only the cost-aware planners apply.
QueryBatch& Maze32(bool decay) {
  static QueryBatch batches[2];
  QueryBatch& b = batches[decay];
  if (b.snapshot) return b;
  b.snapshot = b.maps.Set(testing::CorridorMaze(512, 32, 1), "maze512-32");
  b.costmap = decay ? planning::CostmapOptions{1.0, true, 3.0, 1.0} : planning::CostmapOptions{0.0, true};
  const planning::Costmap costmap(std::shared_ptr<const OccupancyGrid>(b.snapshot, &b.snapshot->grid), b.costmap);
  const OccupancyGrid& g = b.snapshot->grid;
  std::mt19937 rng(32);
  std::uniform_int_distribution<int> coord(0, 511);
  planning::PlanningEngine engine(
      b.maps, {.costmap = b.costmap, .default_planner = "dijkstra", .start_recovery_radius = 0.0, .velocity = {}});
  planning::RegisterDefaultPlanners(engine);
  while (b.scenarios.size() < 1000) {
    MovingAiScenario s;
    s.start_x = coord(rng), s.start_row = coord(rng), s.goal_x = coord(rng), s.goal_row = coord(rng);
    const CellIndex a{s.start_x, g.height() - 1 - s.start_row}, z{s.goal_x, g.height() - 1 - s.goal_row};
    if (costmap.IsLethal(a) || costmap.IsLethal(z)) continue;
    if (!decay)
      s.optimal_length = engine.ComputePath(g.CellCenter(a), g.CellCenter(z), "dijkstra", {{"smooth", 0.0}}).length;
    s.decimals = 8;
    b.scenarios.push_back(s);
  }
  return b;
}

QueryBatch& Arena() {
  static QueryBatch b;
  if (b.snapshot) return b;
  const std::string map = std::string(NAVD_SOURCE_DIR) + "/tests/data/movingai/arena.map";
  b.snapshot = b.maps.Set(LoadMovingAiMap(map), "arena");
  b.scenarios = LoadMovingAiScenarios(map + ".scen");
  b.costmap = {0.0, true};
  return b;
}

void RunBatch(benchmark::State& state, QueryBatch& batch, const std::string& planner) {
  planning::PlanningEngine engine(
      batch.maps, {.costmap = batch.costmap, .default_planner = planner, .start_recovery_radius = 0.0, .velocity = {}});
  planning::RegisterDefaultPlanners(engine);
  engine.CurrentCostmap();
  planning::ScenarioReport report;
  for (auto _ : state) report = planning::RunScenarios(engine, batch.snapshot->grid, batch.scenarios, planner);
  state.counters["median_ms"] = report.median_ms;
  state.counters["p99_ms"] = report.p99_ms;
  if (!batch.costmap.decay_radius) state.counters["optimal"] = static_cast<double>(report.passed);
  state.counters["queries"] = static_cast<double>(report.total);
}

void BM_Maze32Queries(benchmark::State& state, const std::string& planner) { RunBatch(state, Maze32(false), planner); }
void BM_Maze32DecayQueries(benchmark::State& state, const std::string& planner) {
  RunBatch(state, Maze32(true), planner);
}
void BM_ArenaQueries(benchmark::State& state, const std::string& planner) { RunBatch(state, Arena(), planner); }
BENCHMARK_CAPTURE(BM_Maze32Queries, astar, std::string("astar"))->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_Maze32Queries, dijkstra, std::string("dijkstra"))->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_Maze32Queries, jps, std::string("jps"))->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_Maze32DecayQueries, astar, std::string("astar"))->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_Maze32DecayQueries, dijkstra, std::string("dijkstra"))->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_ArenaQueries, astar, std::string("astar"))->Iterations(20)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ArenaQueries, dijkstra, std::string("dijkstra"))->Iterations(20)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ArenaQueries, jps, std::string("jps"))->Iterations(20)->Unit(benchmark::kMillisecond);

// Seed 002's comparison of A* and D*: plan on a 512 x 512 map with 20% random obstacles, then 1%
// of the cells change and the plan is repaired. Reports time and states processed (expansions,
// per replan) for D* Lite's repairs against A* planning again from scratch. Four kinds of change:
//   spread    random toggles over the whole map, all at once;
//   local     random toggles within 60 cells of the robot, all at once (a quarter of that disc);
//   obstacle  an unknown wall across the way 40 cells ahead of the robot, as long as it takes for
//             1% of the map's cells to change (about 330 cells), all at once;
//   drive     how D* Lite is used, and how seed 002's robot met its changes: the robot drives its
//             path and its sensors find small unknown obstacles ahead as it goes (10 x 10 cells,
//             centred 12 cells ahead of where it replans, one find every 8 cells of travel) until
//             1% of the map's cells have changed, each find followed by a replan (~34).
enum class Change { kSpread, kLocal, kObstacle, kDrive };

struct ReplanCase {
  std::shared_ptr<OccupancyGrid> before;
  std::vector<std::vector<std::pair<CellIndex, bool>>> finds;   // the changes before each replan
  std::vector<CellIndex> starts;                                // the robot at each replan
  std::vector<std::shared_ptr<const planning::Costmap>> after;  // the map after each find
  CellIndex start{0, 0}, goal{511, 511};
};

ReplanCase MakeReplanCase(Change kind) {
  ReplanCase rc;
  rc.before = std::make_shared<OccupancyGrid>(512, 512, 1.0, Point2::Zero());
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> coord(0, 511);
  for (int i = 0; i < 512 * 512 / 5; ++i) rc.before->set({coord(rng), coord(rng)}, OccupancyGrid::kOccupied);
  if (kind != Change::kSpread) rc.start = {128, 128};
  rc.before->set(rc.start, OccupancyGrid::kFree);
  rc.before->set(rc.goal, OccupancyGrid::kFree);
  auto grid = std::make_shared<OccupancyGrid>(*rc.before);
  const size_t wanted = 512 * 512 / 100;
  std::vector<uint8_t> changed(512 * 512, 0);
  std::vector<std::pair<CellIndex, bool>> changes;
  auto change = [&](const CellIndex& cell, bool block) {
    if (!grid->Contains(cell) || cell == rc.start || cell == rc.goal || changed[grid->Flat(cell)]) return;
    if ((grid->at(cell) == OccupancyGrid::kFree) != block) return;
    changed[grid->Flat(cell)] = 1;
    grid->set(cell, block ? OccupancyGrid::kOccupied : OccupancyGrid::kFree);
    changes.emplace_back(cell, block);
  };
  auto replan_at = [&](const CellIndex& at) {
    rc.finds.push_back(std::move(changes));
    changes.clear();
    rc.starts.push_back(at);
    rc.after.push_back(std::make_shared<const planning::Costmap>(std::make_shared<OccupancyGrid>(*grid),
                                                                 planning::CostmapOptions{0.0, true}));
  };
  if (kind == Change::kDrive) {
    planning::DStarLite dstar(planning::Costmap(rc.before, {0.0, true}), rc.start, rc.goal);
    dstar.ComputeShortestPath();
    for (size_t total = 0; total < wanted;) {
      const std::vector<CellIndex> path = dstar.Path();
      if (path.size() < 40) break;
      const CellIndex c = path[20], at = path[8];
      for (int y = c.y - 4; y <= c.y + 5; ++y)
        for (int x = c.x - 4; x <= c.x + 5; ++x)
          if (std::max(std::abs(x - at.x), std::abs(y - at.y)) > 1) change({x, y}, true);
      total += changes.size();
      for (const auto& [cell, blocked] : changes) dstar.SetBlocked(cell, blocked);
      dstar.MoveStart(at);
      if (!dstar.ComputeShortestPath()) break;
      replan_at(at);
    }
    return rc;
  }
  if (kind == Change::kObstacle) {
    const double cx = rc.start.x + 28.0, cy = rc.start.y + 28.0;
    for (int half = 1; changes.size() < wanted; ++half)
      for (int y = 0; y < 512; ++y)
        for (int x = 0; x < 512 && changes.size() < wanted; ++x) {
          const double along = ((x - cx) + (y - cy)) / std::sqrt(2.0), across = ((x - cx) - (y - cy)) / std::sqrt(2.0);
          if (std::abs(along) <= 5.0 && std::abs(across) <= half) change({x, y}, true);
        }
  } else {
    std::uniform_int_distribution<int> near(-60, 60);
    while (changes.size() < wanted) {
      const CellIndex cell = kind == Change::kLocal ? CellIndex{rc.start.x + near(rng), rc.start.y + near(rng)}
                                                    : CellIndex{coord(rng), coord(rng)};
      if (kind == Change::kLocal && std::hypot(cell.x - rc.start.x, cell.y - rc.start.y) > 60) continue;
      if (grid->Contains(cell)) change(cell, grid->at(cell) == OccupancyGrid::kFree);
    }
  }
  replan_at(rc.start);
  return rc;
}

const ReplanCase& Replan512(Change kind) {
  static const ReplanCase cases[] = {MakeReplanCase(Change::kSpread), MakeReplanCase(Change::kLocal),
                                     MakeReplanCase(Change::kObstacle), MakeReplanCase(Change::kDrive)};
  return cases[static_cast<int>(kind)];
}

void BM_Replan_AStarFromScratch(benchmark::State& state, Change kind) {
  const ReplanCase& rc = Replan512(kind);
  uint64_t expansions = 0;
  for (auto _ : state) {
    expansions = 0;
    for (size_t k = 0; k < rc.finds.size(); ++k) {
      const auto p = planning::GridAStarPlanner().Plan(*rc.after[k], rc.starts[k], rc.goal,
                                                       {{"diagonal", 1.0}, {"cost_weight", 0.0}}, {});
      expansions += p.expansions;
      benchmark::DoNotOptimize(p);
    }
  }
  state.counters["replans"] = static_cast<double>(rc.finds.size());
  state.counters["states_processed"] = static_cast<double>(expansions) / std::max<size_t>(1, rc.finds.size());
}

void BM_Replan_DStarLiteInitial(benchmark::State& state, Change kind) {
  const ReplanCase& rc = Replan512(kind);
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

void BM_Replan_DStarLiteRepair(benchmark::State& state, Change kind) {
  const ReplanCase& rc = Replan512(kind);
  planning::Costmap before(rc.before, {0.0, true});
  uint64_t expansions = 0;
  for (auto _ : state) {
    state.PauseTiming();
    auto dstar = std::make_unique<planning::DStarLite>(before, rc.start, rc.goal);
    dstar->ComputeShortestPath();
    const uint64_t initial = dstar->expansions();
    state.ResumeTiming();
    for (size_t k = 0; k < rc.finds.size(); ++k) {
      for (const auto& [cell, blocked] : rc.finds[k]) dstar->SetBlocked(cell, blocked);
      dstar->MoveStart(rc.starts[k]);
      dstar->ComputeShortestPath();
    }
    expansions = dstar->expansions() - initial;
    state.PauseTiming();
    dstar.reset();
    state.ResumeTiming();
  }
  state.counters["replans"] = static_cast<double>(rc.finds.size());
  state.counters["states_processed"] = static_cast<double>(expansions) / std::max<size_t>(1, rc.finds.size());
}

#define NAVD_REPLAN_BENCHMARKS(bm)                                                   \
  BENCHMARK_CAPTURE(bm, spread, Change::kSpread)->Unit(benchmark::kMillisecond);     \
  BENCHMARK_CAPTURE(bm, local, Change::kLocal)->Unit(benchmark::kMillisecond);       \
  BENCHMARK_CAPTURE(bm, obstacle, Change::kObstacle)->Unit(benchmark::kMillisecond); \
  BENCHMARK_CAPTURE(bm, drive, Change::kDrive)->Unit(benchmark::kMillisecond)
NAVD_REPLAN_BENCHMARKS(BM_Replan_AStarFromScratch);
NAVD_REPLAN_BENCHMARKS(BM_Replan_DStarLiteInitial);
NAVD_REPLAN_BENCHMARKS(BM_Replan_DStarLiteRepair);

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
    speed[i] =
        evt.values()[i] <= 0.0 ? 0.0 : std::max(0.05, std::log1p(std::min(evt.values()[i], 2.0)) / std::log1p(2.0));
  for (auto _ : state) benchmark::DoNotOptimize(planning::FastMarch(n, n, 0.05, speed, {500, 500}));
}
BENCHMARK(BM_FastMarching1000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
