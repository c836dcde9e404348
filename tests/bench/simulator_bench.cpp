// navsim's speed: ray casting against a 1000 x 1000 grid (5 cm cells, 4 m rays), one robot with a
// 683-beam laser at 10 Hz and odometry at 50 Hz, and ten laser robots with 20 people in the
// warehouse. Counters report rays/s and simulated seconds per wall second (real-time factor).
#include <benchmark/benchmark.h>

#include <random>

#include "services/common/grid_traversal.h"
#include "simulator/laser_scanner.h"
#include "simulator/simulation.h"

namespace navd::sim {
namespace {

// A 50 x 50 m warehouse floor: shelving rows and scattered boxes, about 12% occupied.
OccupancyGrid WarehouseFloor() {
  OccupancyGrid map(1000, 1000, 0.05, {0, 0});
  for (double x = 2.0; x < 48.0; x += 4.0) {
    for (double y = 2.0; y < 46.0; y += 11.0) map.FillBox({x, y}, {x + 1.0, y + 8.0});
  }
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0, 50);
  for (int i = 0; i < 300; ++i) {
    const Point2 c(u(rng), u(rng));
    map.FillBox(c, c + Point2(0.3, 0.3));
  }
  return map;
}

// Rays as a laser casts them: the direction is a unit vector it keeps per beam (no trigonometry
// per ray).
struct Rays {
  std::vector<Point2> origins;
  std::vector<Point2> directions;
};

Rays RandomRays(const OccupancyGrid& map, int n) {
  Rays r;
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(0, 50), a(-M_PI, M_PI);
  while (static_cast<int>(r.origins.size()) < n) {
    const Point2 o(u(rng), u(rng));
    if (map.IsOccupied(map.CellOf(o))) continue;
    r.origins.push_back(o);
    const double angle = a(rng);
    r.directions.emplace_back(std::cos(angle), std::sin(angle));
  }
  return r;
}

void BM_RayCastBlockLeaps(benchmark::State& state) {
  const OccupancyGrid map = WarehouseFloor();
  const RayCaster caster(map);
  const Rays rays = RandomRays(map, 4096);
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(caster.Cast(rays.origins[i & 4095], rays.directions[i & 4095], 4.0));
    ++i;
  }
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RayCastBlockLeaps);

// Whole 683-beam URG scans (no noise, no people) from random free spots of the same floor: the
// rays as the simulated laser casts them.
void BM_LaserScanRays(benchmark::State& state) {
  const OccupancyGrid map = WarehouseFloor();
  const RayCaster caster(map);
  const Rays rays = RandomRays(map, 256);
  LaserDescription urg;
  urg.noise = 0.0;
  const LaserScanner laser(urg);
  std::mt19937_64 rng(4);
  size_t i = 0;
  for (auto _ : state) {
    const Pose2 pose(rays.origins[i & 255].x(), rays.origins[i & 255].y(),
                     std::atan2(rays.directions[i & 255].y(), rays.directions[i & 255].x()));
    benchmark::DoNotOptimize(laser.Scan(pose, caster, {}, -1, rng));
    ++i;
  }
  state.counters["rays/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * urg.beams, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_LaserScanRays);

// The plain cell walk, for the ratio.
void BM_RayCastCellWalk(benchmark::State& state) {
  const OccupancyGrid map = WarehouseFloor();
  const Rays rays = RandomRays(map, 4096);
  size_t i = 0;
  for (auto _ : state) {
    const Point2 o = rays.origins[i & 4095];
    double hit = 4.0;
    TraverseSegment(map, o, o + 4.0 * rays.directions[i & 4095], [&](const CellIndex& c, double t) {
      if (map.Contains(c) && !map.IsOccupied(c)) return true;
      hit = t;
      return false;
    });
    benchmark::DoNotOptimize(hit);
    ++i;
  }
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RayCastCellWalk);

// Drives every robot in slow circles, so lasers sweep and bodies move.
void Run(benchmark::State& state, const Scenario& scenario) {
  Simulation sim(scenario, {});
  double simulated = 0.0;
  for (auto _ : state) {
    for (size_t r = 0; r < sim.robots().size(); ++r) sim.Command(r, {0.2, 0.0, 0.3});
    sim.Step();
    simulated += sim.options().physics_step;
  }
  state.counters["realtime_x"] = benchmark::Counter(simulated, benchmark::Counter::kIsRate);
}

void BM_OneRobotLaser683At10HzOdom50Hz(benchmark::State& state) {
  Scenario s = ScenarioFromWorld(DefaultWorld());  // URG-04LX: 683 beams, 10 Hz; odometry 50 Hz
  Run(state, s);
}
BENCHMARK(BM_OneRobotLaser683At10HzOdom50Hz);

void BM_TenRobotsTwentyPeopleWarehouse(benchmark::State& state) {
  Scenario s = ScenarioFromWorld(DefaultWorld());
  const Pose2 starts[10] = {{0.8, 1.0, 1.57}, {0.8, 4.0, 1.57}, {0.8, 7.0, 1.57}, {3.0, 2.6, 0.0},  {5.0, 5.0, 0.0},
                            {8.8, 8.8, 3.14}, {8.5, 3.3, 0.0},  {4.5, 9.2, 0.0},  {8.6, 5.6, 3.14}, {3.5, 7.1, 0.0}};
  s.robots.clear();
  for (int i = 0; i < 10; ++i) {
    RobotSpec r;
    r.name = "robot" + std::to_string(i);
    r.start = starts[i];
    r.body = s.world.robot;
    r.laser = s.world.laser;
    r.encoders = r.bumper = true;
    s.robots.push_back(r);
  }
  CrowdDescription c;
  c.area = {{0.2, 0.2}, {9.8, 9.8}};
  c.street = false;
  c.initial_min = c.initial_max = c.max_people = 20;
  c.arrival_rate = 0.0;
  c.speed_mean = 0.8;
  c.spawn_clearance = 0.2;
  s.crowd = c;
  Run(state, s);
}
BENCHMARK(BM_TenRobotsTwentyPeopleWarehouse);

}  // namespace
}  // namespace navd::sim

BENCHMARK_MAIN();
