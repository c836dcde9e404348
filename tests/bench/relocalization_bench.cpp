// Global relocalisation success rate: the robot at N random free poses of the warehouse, the
// particle filter (or the histogram filter) with no prior (GlobalRelocalize); the robot turns on
// the spot for 12 s (the wake-up behaviour: look around) and stands for one second. Success:
// within 0.1 m and 0.1 rad.
//   build/tests/relocalization_bench [--runs N] [--seed S] [--localizer amcl|histogram]
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "services/common/world.h"
#include "services/localization/histogram_localizer.h"
#include "services/localization/particle_filter.h"
#include "services/common/diff_drive.h"
#include "simulator/simulation.h"
#include "tests/support/simulated_drive.h"

int main(int argc, char** argv) {
  using namespace navd;
  CLI::App app{"global relocalisation success rate in the warehouse"};
  int runs = 100;
  uint64_t seed = 1;
  app.add_option("--runs", runs)->check(CLI::Range(1, 10000));
  app.add_option("--seed", seed);
  std::string method = "amcl";
  app.add_option("--localizer", method, "amcl (particle filter) or histogram (grid)")
      ->check(CLI::IsMember({"amcl", "histogram"}));
  CLI11_PARSE(app, argc, argv);

  const World base = DefaultWorld();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(0.0, 10.0), ut(-M_PI, M_PI);
  int success = 0;
  std::vector<double> errors;
  const auto t0 = std::chrono::steady_clock::now();
  for (int run = 0; run < runs; ++run) {
    World world = base;
    do {  // a random pose where the robot fits
      world.start = {ux(rng), ux(rng), ut(rng)};
    } while (!world.map.ContainsPoint(world.start.translation()) ||
             world.map.DiscHitsObstacle(world.start.translation(), world.robot.radius + 0.05));
    sim::SimulationOptions so;
    so.seed = seed * 1000 + run;
    sim::Simulation s(world, so);
    std::unique_ptr<localization::Localizer> localizer;
    if (method == "histogram") {
      localizer = std::make_unique<localization::HistogramLocalizer>(world.map);
    } else {
      localization::ParticleFilterOptions po;
      po.seed = seed * 7919 + run;
      localizer = std::make_unique<localization::ParticleFilterLocalizer>(world.map, po);
    }
    localization::Localizer& pf = *localizer;
    pf.AddOdometry({s.robot().base().odom_pose(), Eigen::Matrix3d::Zero(), 0.0});
    pf.GlobalRelocalize();
    while (s.now() < 13.0) {
      s.Command(0, {0.0, 0.0, s.now() < 12.0 ? 0.6 : 0.0});
      const auto out = s.Step();
      if (out.robots[0].odom)
        pf.AddOdometry({s.robot().base().odom_pose(), s.robot().base().odom_covariance(), s.now()});
      if (out.robots[0].scan) {
        // Stamped now: the filter moves particles to the odometry of the scan's own time.
        pf.AddScan(localization::ToScan(s, *out.robots[0].scan));
      }
    }
    const Pose2 e = pf.Estimate().pose, t = s.robot().base().true_pose();
    const double err = std::hypot(e.x - t.x, e.y - t.y), herr = std::abs(NormalizeAngle(e.theta - t.theta));
    errors.push_back(err);
    if (err < 0.1 && herr < 0.1) {
      ++success;
    } else {
      std::fprintf(stderr, "\n  run %d from (%.2f, %.2f, %.2f): error %.3f m, %.3f rad\n", run, t.x, t.y, t.theta, err,
                   herr);
    }
    std::fprintf(stderr, "\r  %d/%d runs, %d found", run + 1, runs, success);
  }
  std::sort(errors.begin(), errors.end());
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::fprintf(stderr, "\n");
  std::printf("global relocalisation: %d/%d (%.0f%%) within 0.1 m and 0.1 rad; median error %.3f m; %.1f s\n", success,
              runs, 100.0 * success / runs, errors[errors.size() / 2], wall);
  return 0;
}
