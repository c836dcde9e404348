// Localiser speed on the warehouse with scans from navsim's laser model: one particle filter update
// (likelihood field on 60 or 90 beams, or the beam model's ray casts on 30; resampling when due)
// with 2,000 particles, one EKF correction (scan-to-map fit) and one calibration check; and the
// scan search, within the nearby reset's 5 m window and over the whole map.
//   build/tests/localization_bench
#include <benchmark/benchmark.h>

#include <memory>

#include "services/common/world.h"
#include "services/localization/ekf_localizer.h"
#include "services/localization/nearby_reset.h"
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

// One scan searched for, as the nearby reset does (an estimate 2.5 m off, every heading within
// 5 m) and as the wake-up's whole-map search does; the scan's end points in the robot frame.
void ScanSearchBench(benchmark::State& state, bool whole_map) {
  const World world = DefaultWorld();
  const localization::LikelihoodField field(world.map);
  const localization::GlobalScanSearch search(world.map, field);
  std::mt19937_64 rng(1);
  const localization::ScanReading scan = localization::SimulatedScan(world, world.start, rng);
  const std::vector<Point2> points = localization::ScanEndPoints(scan, 0);
  const Pose2 off{world.start.x, world.start.y - 2.5, world.start.theta + 0.5};
  const localization::NearbyReset reset;
  size_t found = 0;
  for (auto _ : state) {
    if (whole_map) {
      found += search.Search(points).size();
    } else {
      found += reset.Check(search, off, 0.5, points).has_value();
    }
  }
  benchmark::DoNotOptimize(found);
}
void BM_NearbyResetCheck(benchmark::State& state) { ScanSearchBench(state, false); }
BENCHMARK(BM_NearbyResetCheck)->Unit(benchmark::kMillisecond);
void BM_WholeMapScanSearch(benchmark::State& state) { ScanSearchBench(state, true); }
BENCHMARK(BM_WholeMapScanSearch)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
