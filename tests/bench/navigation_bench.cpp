// The delivery scheduler's cost (path lengths given; navd adds one planned path per pair of
// stops): the exact schedule up to 7 tasks, the heuristic beyond. The crowd RRT's plan (book
// chapter 7, 2000 vertices) among N walkers in the street, what the people-aware controller pays
// every 0.5 s.
#include <benchmark/benchmark.h>

#include <random>

#include "services/navigation/delivery_scheduler.h"
#include "services/planning/crowd_rrt.h"

namespace navd::navigation {
namespace {

void BM_ScheduleDeliveries(benchmark::State& state) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 20.0);
  std::vector<DeliveryTask> tasks;
  tasks.reserve(state.range(0));
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

void BM_CrowdRrtPlan(benchmark::State& state) {
  OccupancyGrid g(1000, 80, 0.1, Point2::Zero());
  g.FillBox({0.0, 0.0}, {100.0, 0.1});
  g.FillBox({0.0, 7.9}, {100.0, 8.0});
  const planning::Costmap cm(std::make_shared<const OccupancyGrid>(std::move(g)),
                             planning::CostmapOptions{0.4, true, 0.5, 3.0});
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(20.0, 80.0), y(0.6, 7.4), dir(0.0, 1.0);
  planning::CrowdRrtRequest r;
  r.start = {40.0, 4.0, 0.0, 1.5, 0.0, 0.0};
  r.goal = {52.0, 4.0};
  for (double px = 40.0; px <= 52.0 + 1e-9; px += 0.25) r.path.emplace_back(px, 4.0);
  r.limits = {1.5, 2.0, 1.0, 4.0};
  while (static_cast<int>(r.people.size()) < state.range(0)) {
    const Point2 p(x(rng), y(rng));
    if (Distance(p, r.start.position()) > 2.0) r.people.push_back({p, {dir(rng) < 0.5 ? -1.3 : 1.3, 0.0}, 0.25, true});
  }
  planning::CrowdRrtOptions o;
  o.desired_speed = 1.5;
  int vertices = 0, pruned = 0;
  for (auto _ : state) {
    ++r.seed;
    const planning::CrowdTrajectory t = planning::PlanCrowdRrt(cm, r, o);
    vertices += t.tree_size;
    pruned += t.pruned;
  }
  state.counters["vertices"] = benchmark::Counter(vertices, benchmark::Counter::kAvgIterations);
  state.counters["pruned"] = benchmark::Counter(pruned, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_CrowdRrtPlan)->Arg(0)->Arg(10)->Arg(20)->Arg(40)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace navd::navigation

BENCHMARK_MAIN();
