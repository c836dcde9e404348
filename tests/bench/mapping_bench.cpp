// Mapping speed: one laser scan integrated into an occupancy grid, a scan match, a whole SLAM
// step, and the scan consistency of a dense log. Medians are the figures reported in issue notes.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "services/common/ray_caster.h"
#include "services/mapping/correlative_scan_matcher.h"
#include "services/mapping/occupancy_grid_mapper.h"
#include "services/mapping/scan_consistency.h"

namespace navd {
namespace {

// A 40 x 40 m floor of rooms (walls every 5 m with doors), 5 cm cells.
const OccupancyGrid& Floor() {
  static const OccupancyGrid g = [] {
    OccupancyGrid grid(800, 800, 0.05, Point2::Zero());
    for (int k = 0; k <= 8; ++k) {
      const double at = 5.0 * k;
      for (double s = 0.0; s < 40.0; s += 5.0) {
        grid.FillBox({at - 0.05, s}, {at + 0.05, s + 3.8});  // vertical walls, 1.2 m doors
        grid.FillBox({s, at - 0.05}, {s + 3.8, at + 0.05});
      }
    }
    return grid;
  }();
  return g;
}

// A Hokuyo UTM-30LX-like scan: 683 beams over 240 degrees (0.352 deg apart), 30 m range.
std::vector<float> Scan683(const Pose2& pose) {
  static const RayCaster caster(Floor());
  std::vector<float> ranges;
  const double fov = 240.0 * M_PI / 180.0, inc = fov / 682.0;
  ranges.reserve(683);
  for (int i = 0; i < 683; ++i)
    ranges.push_back(static_cast<float>(caster.Cast(pose.translation(), pose.theta - fov / 2 + i * inc, 30.0)));
  return ranges;
}

void BM_IntegrateScan683Into5cmGrid(benchmark::State& state) {
  mapping::MapperOptions o;
  o.resolution = 0.05;
  mapping::OccupancyGridMapper mapper({0.0, 0.0}, {40.0, 40.0}, o);
  const Pose2 pose{12.5, 17.5, 0.4};
  const std::vector<float> ranges = Scan683(pose);
  const double fov = 240.0 * M_PI / 180.0;
  for (auto _ : state) mapper.AddScan(pose, ranges, -fov / 2, fov / 682.0);
}
BENCHMARK(BM_IntegrateScan683Into5cmGrid)->Unit(benchmark::kMicrosecond);

void BM_CorrelativeMatch683(benchmark::State& state) {
  const Pose2 reference{12.5, 17.5, 0.4}, truth{12.8, 17.3, 0.5};
  const double fov = 240.0 * M_PI / 180.0, inc = fov / 682.0;
  auto points = [&](const Pose2& pose, bool world) {
    std::vector<Point2> out;
    const std::vector<float> r = Scan683(pose);
    for (int i = 0; i < 683; ++i) {
      if (r[i] >= 30.0f) continue;
      const double a = -fov / 2 + i * inc;
      const Point2 p(r[i] * std::cos(a), r[i] * std::sin(a));
      out.push_back(world ? pose * p : p);
    }
    return out;
  };
  const mapping::CorrelationGrid grid(points(reference, true), 0.05, 0.05);
  const std::vector<Point2> scan = mapping::ThinPoints(points(truth, false), 0.1);
  for (auto _ : state)
    benchmark::DoNotOptimize(mapping::MatchScan(grid, scan, {truth.x + 0.1, truth.y - 0.1, truth.theta + 0.05}, {}));
}
BENCHMARK(BM_CorrelativeMatch683)->Unit(benchmark::kMillisecond);

// A front end's local map: ten 683-beam scans 0.3 m apart along a room's middle, their echoes
// smeared into the 5 cm lookup grid (built again for every scan SLAM matches).
void BM_CorrelationGridOfTenScans683(benchmark::State& state) {
  const double fov = 240.0 * M_PI / 180.0, inc = fov / 682.0;
  std::vector<Point2> reference;
  for (int k = 0; k < 10; ++k) {
    const Pose2 pose{11.0 + 0.3 * k, 17.5, 0.1 * k};
    const std::vector<float> r = Scan683(pose);
    for (int i = 0; i < 683; ++i)
      if (r[i] < 30.0f)
        reference.push_back(pose * Point2(r[i] * std::cos(-fov / 2 + i * inc), r[i] * std::sin(-fov / 2 + i * inc)));
  }
  for (auto _ : state) benchmark::DoNotOptimize(mapping::CorrelationGrid(reference, 0.05, 0.05));
}
BENCHMARK(BM_CorrelationGridOfTenScans683)->Unit(benchmark::kMillisecond);

// The scan consistency of a dense drive: 300 683-beam scans 4 cm apart, back and forth across one
// room, each wall seen by hundreds of scans (a robot's own 40 Hz log, unthinned), every return
// judged against the lines of the others.
void BM_ScanConsistencyOf300DenseScans683(benchmark::State& state) {
  const double fov = 240.0 * M_PI / 180.0, inc = fov / 682.0;
  std::vector<Pose2> poses;
  std::vector<std::vector<Point2>> returns;
  for (int k = 0; k < 300; ++k) {
    const double along = 0.04 * (k % 100);
    const Pose2 pose{11.0 + along, 17.5 + 0.3 * std::sin(0.1 * k), 0.01 * k};
    const std::vector<float> r = Scan683(pose);
    std::vector<Point2> scan;
    for (int i = 0; i < 683; ++i)
      if (r[i] < 15.0f) scan.emplace_back(r[i] * std::cos(-fov / 2 + i * inc), r[i] * std::sin(-fov / 2 + i * inc));
    poses.push_back(pose);
    returns.push_back(std::move(scan));
  }
  const mapping::ScanConsistency consistency(poses, std::move(returns));
  for (auto _ : state) benchmark::DoNotOptimize(consistency.Score());
}
BENCHMARK(BM_ScanConsistencyOf300DenseScans683)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace navd

BENCHMARK_MAIN();
