// The depth camera's cost: one cloud through navd's whole pipeline into the obstacle
// layer (PCL filter, then the voxel layer's clearing and marking) at 640 x 480 and at the default
// 212 x 120, and navsim's rendering of one image. The clouds are rendered by navsim's camera in the
// office_3d scenario, from the robot's start looking down the corridor at a table and a low box.
#include <benchmark/benchmark.h>

#include "services/perception/depth_obstacle_layer.h"
#include "simulator/depth_camera.h"
#include "simulator/scenario.h"
#include "simulator/simulation.h"

namespace navd {
namespace {

const sim::Scenario& Office3d() {
  static const sim::Scenario s = sim::LoadScenarioFile(NAVD_SOURCE_DIR "/worlds/scenarios/office_3d.yaml");
  return s;
}

DepthCameraDescription CameraAt(int width, int height) {
  DepthCameraDescription d = *Office3d().robots[0].camera;
  d.width = width;
  d.height = height;
  return d;
}

std::vector<Eigen::Vector3f> Cloud(const DepthCameraDescription& d, const Pose2& at) {
  const sim::Simulation simulation(Office3d(), {});
  std::mt19937_64 rng(1);
  return sim::DepthCamera(d).Capture(at, simulation.camera_walls(), Office3d().solids, {}, -1, rng);
}

// At the start, and 1.5 m before the table, looking at it from the side.
const Pose2 kViews[] = {{1.0, 6.0, 0.0}, {2.6, 5.9, -0.2}};

void BM_PerceptionPipeline(benchmark::State& state) {
  const DepthCameraDescription d = CameraAt(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  perception::DepthObstacleLayer layer(
      d, perception::DepthObstacleLayerOptions::ForRobot(Office3d().robots[0].body.height));
  layer.SetMap(Office3d().world.map);
  const Pose2 view = kViews[state.range(2)];
  const std::vector<Eigen::Vector3f> cloud = Cloud(d, view);
  double t = 0.0;
  for (auto _ : state) layer.AddCloud(cloud, view, t += 0.066);
  state.counters["points"] = static_cast<double>(cloud.size());
  state.counters["marked_cells"] = static_cast<double>(layer.Obstacles()->size());
}
BENCHMARK(BM_PerceptionPipeline)
    ->Args({640, 480, 0})
    ->Args({640, 480, 1})
    ->Args({212, 120, 0})
    ->Args({212, 120, 1})
    ->Unit(benchmark::kMillisecond);

void BM_DepthCameraRender(benchmark::State& state) {
  const DepthCameraDescription d = CameraAt(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const sim::Simulation simulation(Office3d(), {});
  const sim::DepthCamera camera(d);
  std::mt19937_64 rng(1);
  const Pose2 view = kViews[1];
  for (auto _ : state)
    benchmark::DoNotOptimize(camera.Capture(view, simulation.camera_walls(), Office3d().solids, {}, -1, rng));
}
BENCHMARK(BM_DepthCameraRender)->Args({212, 120})->Args({640, 480})->Unit(benchmark::kMillisecond);

// navsim's office_3d run as its process steps it, with and without the camera (no transport):
// each iteration drives the robot from its start down the corridor past the table and the low box
// and round, 20 s of simulated time from a fresh simulation. Counter: simulated seconds per wall
// second.
void BM_SimulateOffice3d(benchmark::State& state) {
  sim::Scenario s = Office3d();
  if (state.range(0) == 0) s.robots[0].camera.reset();
  constexpr int kSteps = 2000;  // 20 s at the simulator's 100 Hz
  for (auto _ : state) {
    state.PauseTiming();
    sim::Simulation simulation(s, {});
    state.ResumeTiming();
    for (int i = 0; i < kSteps; ++i) {
      if (i % 10 == 0) simulation.Command(0, {0.4, 0.0, i < kSteps / 2 ? 0.0 : 0.5});
      benchmark::DoNotOptimize(simulation.Step());
    }
  }
  state.counters["real_time_factor"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * kSteps * 0.01, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SimulateOffice3d)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace navd

BENCHMARK_MAIN();
