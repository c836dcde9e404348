// Load test of PlanningService.ComputePath over real gRPC on loopback: starts a navd on the
// embedded warehouse (free port, own DDS domain), then N client threads each send requests between
// random free points for a bounded time. Prints requests/s and latency percentiles.
// With --secure, navd serves TLS with roles (a fresh scripts/make-keystore keystore) and each
// client sends an operator token: the cost of security, beside a plain run.
//   build/tests/grpc_plan_load [--clients N] [--seconds S] [--max-requests M] [--cost-decay M] [--secure]
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <optional>
#include <random>
#include <thread>

#include <CLI/CLI.hpp>

#include "services/common/world.h"
#include "services/planning/costmap.h"
#include "tests/support/keystore.h"
#include "tests/support/navd_fixture.h"

int main(int argc, char** argv) {
  CLI::App app{"gRPC ComputePath load test against a real navd"};
  int clients = 2;
  double seconds = 5.0;
  long max_requests = 200000;
  app.add_option("--clients", clients)->check(CLI::Range(1, 64));
  app.add_option("--seconds", seconds)->check(CLI::Range(0.5, 120.0));
  app.add_option("--max-requests", max_requests)->check(CLI::PositiveNumber);
  std::string cost_decay = "0.5";
  app.add_option("--cost-decay", cost_decay, "navd --cost-decay (0: shortest paths, no decay layer)");
  bool secure = false;
  app.add_flag("--secure", secure, "TLS and an operator bearer token on every call");
  CLI11_PARSE(app, argc, argv);

  using namespace navd;
  navd::testing::StackOptions options;
  options.start_sim = false;  // planning needs only the map
  options.use_sim_time = false;
  options.navd_args = {"--cost-decay", cost_decay};
  std::optional<navd::testing::Keystore> keys;
  ClientOptions client_options("", 5.0);
  if (secure) {
    keys.emplace();
    options.navd_args.insert(options.navd_args.end(), {"--tls-cert", keys->tls("navd.pem"), "--tls-key",
                                                       keys->tls("navd.key"), "--auth-tokens", keys->tokens()});
    options.client = keys->Client("admin");
    client_options = keys->Client("operator");
  }
  navd::testing::NavdStack stack(options);

  // Random query points on cells free of the inflated obstacles, fixed seed.
  const World world = DefaultWorld();
  planning::Costmap costmap(std::make_shared<OccupancyGrid>(world.map), {world.robot.radius + 0.10, true});
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  std::vector<Point2> points;
  while (points.size() < 512) {
    const Point2 p(u(rng), u(rng));
    const CellIndex c = world.map.CellOf(p);
    if (world.map.Contains(c) && !costmap.IsLethal(c)) points.push_back(p);
  }

  std::atomic<long> issued{0};
  std::vector<std::vector<double>> latencies(clients);
  std::atomic<long> errors{0};
  std::vector<double> planning_ms(clients, 0.0);
  const auto start = std::chrono::steady_clock::now();
  const auto end = start + std::chrono::duration<double>(seconds);
  std::vector<std::thread> threads;
  threads.reserve(clients);
  for (int t = 0; t < clients; ++t) {
    threads.emplace_back([&, t] {
      // A channel per client, as separate processes would have.
      const std::unique_ptr<Client> channel = stack.MakeClient(client_options);
      Client& client = *channel;
      size_t k = t * 7;
      while (std::chrono::steady_clock::now() < end && issued.fetch_add(1) < max_requests) {
        const Point2& a = points[k++ % points.size()];
        const Point2& b = points[(k * 31) % points.size()];
        const auto t0 = std::chrono::steady_clock::now();
        try {
          planning_ms[t] += client.ComputePath(a.x(), a.y(), b.x(), b.y()).planning_time() * 1e3;
        } catch (const ClientError&) {
          ++errors;  // NOT_FOUND for the odd unreachable pair; still a served request
        }
        latencies[t].push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      }
    });
  }
  for (auto& th : threads) th.join();
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<double> all;
  for (const auto& l : latencies) all.insert(all.end(), l.begin(), l.end());
  std::sort(all.begin(), all.end());
  auto pct = [&](double q) {
    return all.empty() ? 0.0 : all[std::min(all.size() - 1, static_cast<size_t>(q * all.size()))];
  };
  double planning_total = 0;
  for (double v : planning_ms) planning_total += v;
  std::printf(
      "ComputePath on the warehouse: %d clients, %zu requests in %.2f s = %.0f req/s; latency p50 %.3f ms, "
      "p90 %.3f ms, p99 %.3f ms; mean planning time in navd %.3f ms; %ld errors (unreachable pairs)\n",
      clients, all.size(), elapsed, all.size() / elapsed, pct(0.5), pct(0.9), pct(0.99),
      planning_total / std::max<size_t>(1, all.size()), errors.load());
  return 0;
}
