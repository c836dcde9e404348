// Localiser speed on the warehouse with scans from navsim's laser model: one particle filter update
// (likelihood field on 60 or 90 beams, or the beam model's ray casts on 30; resampling when due)
// with 2,000 particles, one EKF correction (scan-to-map fit) and one calibration check.
//   build/tests/localization_bench
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>

#include "services/common/ray_caster.h"
#include "services/common/world.h"
#include "services/localization/ekf_localizer.h"
#include "services/localization/global_scan_search.h"
#include "services/localization/likelihood_field.h"
#include "services/localization/scan_points.h"
#include "services/localization/odometric_calibration.h"
#include "services/localization/particle_filter.h"
#include "tests/support/simulated_drive.h"

namespace {

using namespace navd;

void BM_ParticleFilterUpdate(benchmark::State& state) {
  const World world = DefaultWorld();
  localization::ParticleFilterOptions o;
  o.min_particles = o.max_particles = static_cast<int>(state.range(0));
  o.beams = static_cast<int>(state.range(1));
  if (state.range(2)) {
    o.sensor_model = localization::SensorModel::kBeam;
    o.beam_model.beams = static_cast<int>(state.range(1));
  }
  localization::ParticleFilterLocalizer pf(world.map, o);
  pf.AddOdometry({{0, 0, 0}, Eigen::Matrix3d::Zero(), 0.0});
  Eigen::Matrix3d prior = Eigen::Matrix3d::Zero();
  prior.diagonal() << 0.04, 0.04, 0.04;
  pf.SetPose(world.start, prior);
  std::mt19937_64 rng(1);
  localization::ScanReading scan = localization::SimulatedScan(world, world.start, rng);
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
BENCHMARK(BM_ParticleFilterUpdate)
    ->ArgNames({"particles", "beams", "beam_model"})
    ->Args({2000, 60, 0})
    ->Args({2000, 90, 0})
    ->Args({2000, 30, 1})
    ->Unit(benchmark::kMillisecond);

// The same scan through the EKF (a Gauss-Newton fit from a pose 5 cm and 0.05 rad off) and through
// the odometric calibration (virtual scans; a search each time, since the pose is off).
template <typename Make>
void CorrectionBench(benchmark::State& state, Make make) {
  const World world = DefaultWorld();
  std::mt19937_64 rng(1);
  localization::ScanReading scan = localization::SimulatedScan(world, world.start, rng);
  auto localizer = make(world);
  double t = 0.0;
  for (auto _ : state) {
    state.PauseTiming();
    t += 1.0;
    localizer->AddOdometry({{0, 0, 0}, Eigen::Matrix3d::Zero(), t});
    localizer->SetPose({world.start.x + 0.05, world.start.y, world.start.theta + 0.05},
                       Eigen::Matrix3d::Identity() * 0.01);
    localizer->AddOdometry({{0.06, 0, 0}, Eigen::Matrix3d::Zero(), t + 0.1});
    scan.stamp = t + 0.1;
    state.ResumeTiming();
    benchmark::DoNotOptimize(localizer->AddScan(scan));
  }
}
void BM_EkfCorrection(benchmark::State& state) {
  CorrectionBench(state, [](const World& w) { return std::make_unique<localization::EkfLocalizer>(w.map); });
}
BENCHMARK(BM_EkfCorrection)->Unit(benchmark::kMillisecond);
void BM_CalibrationSearch(benchmark::State& state) {
  CorrectionBench(state,
                  [](const World& w) { return std::make_unique<localization::OdometricCalibrationLocalizer>(w.map); });
}
BENCHMARK(BM_CalibrationSearch)->Unit(benchmark::kMillisecond);

}  // namespace

// One whole-map scan search (the first step of a global relocalisation), exhaustive over every
// finest block (pyramid_levels 1) or best first down the block pyramid, on the warehouse with a
// scan of navsim's laser, or on the map NAVD_BENCH_MAP names (e.g. one navd-replay --mode map
// built from a real log) with a 360-degree 10 m scan ray-cast at a free pose near its middle.
void BM_GlobalScanSearch(benchmark::State& state) {
  const char* path = std::getenv("NAVD_BENCH_MAP");
  const OccupancyGrid map = path ? LoadAnyMapFile(path) : DefaultWorld().map;
  const localization::LikelihoodField field(map);
  localization::GlobalScanSearchOptions o;
  o.pyramid_levels = static_cast<int>(state.range(0));
  o.blocks_refined = static_cast<int>(state.range(1));
  const localization::GlobalScanSearch search(map, field, o);
  std::vector<Point2> points;
  if (path) {
    const RayCaster caster(map);
    CellIndex cell{map.width() / 2, map.height() / 2};
    for (int r = 0; map.at(cell) != OccupancyGrid::kFree && r < 97 * 97; ++r)
      cell = {std::min(map.width() - 1, map.width() / 2 + r % 97),
              std::min(map.height() - 1, map.height() / 2 + r / 97)};
    const Point2 at = map.CellCenter(cell);
    for (int i = 0; i < 360; ++i) {
      const double a = i * M_PI / 180.0, range = caster.CastOpenEdge(at, 0.3 + a, 10.0);
      if (range < 10.0) points.emplace_back(range * std::cos(a), range * std::sin(a));
    }
  } else {
    const World world = DefaultWorld();
    std::mt19937_64 rng(1);
    points = localization::ScanEndPoints(localization::SimulatedScan(world, world.start, rng), 0);
  }
  for (auto _ : state) benchmark::DoNotOptimize(search.Search(points));
  state.counters["block_scores"] = static_cast<double>(search.last_block_scores());
}
BENCHMARK(BM_GlobalScanSearch)
    ->ArgNames({"pyramid_levels", "blocks_refined"})
    ->Args({1, 300})
    ->Args({4, 300})
    ->Args({4, 30})
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
