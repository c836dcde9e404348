// Particle filter speed: one laser update (likelihood field on 60 beams, resampling when due) with
// 2,000 particles, on the warehouse with scans from navsim's laser model.
//   build/tests/localization_bench
#include <benchmark/benchmark.h>

#include "services/common/world.h"
#include "services/localization/particle_filter.h"
#include "simulator/laser_scanner.h"

namespace {

using namespace navd;

void BM_ParticleFilterUpdate(benchmark::State& state) {
  const World world = DefaultWorld();
  localization::ParticleFilterOptions o;
  o.min_particles = o.max_particles = static_cast<int>(state.range(0));
  o.beams = static_cast<int>(state.range(1));
  localization::ParticleFilterLocalizer pf(world.map, o);
  pf.AddOdometry({{0, 0, 0}, Eigen::Matrix3d::Zero(), 0.0});
  Eigen::Matrix3d prior = Eigen::Matrix3d::Zero();
  prior.diagonal() << 0.04, 0.04, 0.04;
  pf.SetPose(world.start, prior);
  sim::LaserScanner laser(world.laser);
  std::mt19937_64 rng(1);
  localization::ScanReading scan;
  scan.ranges = laser.Scan(world.start, RayCaster(world.map), {}, -1, rng);
  scan.angle_min = laser.angle_min();
  scan.angle_increment = laser.increment();
  scan.range_min = world.laser.range_min;
  scan.range_max = world.laser.range_max;
  double x = 0.0;
  for (auto _ : state) {
    state.PauseTiming();
    // A little motion back and forth makes each scan count as new information.
    x = x > 0 ? 0.0 : 0.06;
    pf.AddOdometry({{x, 0, 0}, Eigen::Matrix3d::Zero(), 0.0});
    state.ResumeTiming();
    benchmark::DoNotOptimize(pf.AddScan(scan));
  }
  state.counters["particles"] = static_cast<double>(pf.particle_count());
}
BENCHMARK(BM_ParticleFilterUpdate)->Args({2000, 60})->Args({2000, 90})->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
