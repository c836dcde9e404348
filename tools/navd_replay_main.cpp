// navd-replay: runs navd's library code over a recorded CARMEN log, as fast as it can.
//   navd-replay --log FILE[.gz] --mode map --out MAP.yaml [--resolution 0.05]
// `map` builds an occupancy grid from the log's (corrected) laser poses and saves it as a ROS
// map_server YAML + PGM, atomically.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "services/common/carmen_log.h"
#include "services/common/error.h"
#include "services/common/map_server_format.h"
#include "services/mapping/occupancy_grid_mapper.h"

namespace {

int BuildMap(const navd::CarmenLog& log, const std::string& out, double resolution) {
  navd::mapping::MapperOptions o;
  o.resolution = resolution;
  // The map covers every beam's end (cut at the usable range), with a margin.
  navd::Point2 lo(1e18, 1e18), hi(-1e18, -1e18);
  for (const auto& s : log.scans) {
    for (size_t i = 0; i < s.ranges.size(); ++i) {
      const double r = std::min<double>(s.ranges[i], o.usable_range);
      const double a = s.pose.theta + navd::CarmenBeamAngle(i, s.ranges.size());
      const navd::Point2 p = s.pose.translation() + r * navd::Point2(std::cos(a), std::sin(a));
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  lo -= navd::Point2(1, 1);
  hi += navd::Point2(1, 1);
  navd::mapping::OccupancyGridMapper mapper(lo, hi, o);
  for (size_t k = 0; k < log.scans.size(); ++k) {
    const auto& s = log.scans[k];
    mapper.AddScan(s.pose, s.ranges, navd::CarmenBeamAngle(0, s.ranges.size()), navd::CarmenBeamAngle(1, s.ranges.size()) - navd::CarmenBeamAngle(0, s.ranges.size()));
    if ((k + 1) % 100 == 0 || k + 1 == log.scans.size()) {
      std::fprintf(stderr, "\r  mapped %zu/%zu scans", k + 1, log.scans.size());
    }
  }
  std::fprintf(stderr, "\n");
  const navd::OccupancyGrid grid = mapper.ToGrid();
  navd::SaveMapServerMap(grid, out);
  std::printf("map: %dx%d cells at %.3f m, origin (%.2f, %.2f), from %zu scans -> %s\n", grid.width(), grid.height(),
              grid.resolution(), grid.origin().x(), grid.origin().y(), log.scans.size(), out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"navd-replay: navd's algorithms over a recorded CARMEN log"};
  std::string log_path, mode = "map", out;
  double resolution = 0.05;
  bool strict = false;
  app.add_option("--log", log_path, "CARMEN log (.log or .log.gz)")->required();
  app.add_option("--mode", mode, "map: build a map from the log's corrected poses")->check(CLI::IsMember({"map"}));
  app.add_option("--out", out, "Output: map_server YAML (the PGM goes beside it)")->required();
  app.add_option("--resolution", resolution, "Map resolution, metres")->check(CLI::Range(0.005, 10.0));
  app.add_flag("--strict", strict, "Stop at the first malformed line instead of skipping it");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    const auto t0 = std::chrono::steady_clock::now();
    const navd::CarmenLog log = navd::ReadCarmenLog(log_path, strict);
    if (log.skipped_lines > 0) std::fprintf(stderr, "navd-replay: skipped %d malformed lines\n", log.skipped_lines);
    const int rc = BuildMap(log, out, resolution);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double span = log.scans.back().timestamp - log.scans.front().timestamp;
    std::printf("replayed %.0f s of log in %.2f s (%.0fx real time)\n", span, wall, wall > 0 ? span / wall : 0.0);
    return rc;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navd-replay: %s\n", e.what());
    return 2;
  }
}
