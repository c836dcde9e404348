// The delivery scheduler's cost (path lengths given; navd adds one planned path per pair of
// stops): the exact schedule up to 7 tasks, the heuristic beyond.
#include <benchmark/benchmark.h>

#include <random>

#include "services/navigation/delivery_scheduler.h"

namespace navd::navigation {
namespace {

void BM_ScheduleDeliveries(benchmark::State& state) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 20.0);
  std::vector<DeliveryTask> tasks;
  for (int i = 0; i < state.range(0); ++i) tasks.push_back({"t", {u(rng), u(rng)}, {u(rng), u(rng)}, i % 2});
  DeliveryScheduleOptions o;
  o.capacity = 3;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        ScheduleDeliveries({10, 10}, tasks, o, [](const Point2& a, const Point2& b) { return Distance(a, b); }));
  }
  state.SetLabel(tasks.size() <= o.exact_up_to ? "exact" : "heuristic");
}
BENCHMARK(BM_ScheduleDeliveries)->Arg(3)->Arg(5)->Arg(7)->Arg(8)->Arg(10)->Arg(25)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace navd::navigation

BENCHMARK_MAIN();
