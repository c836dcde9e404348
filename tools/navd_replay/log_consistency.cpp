#include "tools/navd_replay/log_consistency.h"

#include <cstdio>
#include <stdexcept>
#include <utility>

#include "services/common/scan_reach.h"
#include "services/common/text_file.h"
#include "services/common/tum_trajectory.h"
#include "services/mapping/scan_consistency.h"

namespace navd::replay {
namespace {

// m: the echoes the scan consistency measures, as far as the maps are drawn from each pose.
constexpr double kConsistencyReach = 15.0;

}  // namespace

std::vector<Pose2> LogPoses(const CarmenLog& log) {
  std::vector<Pose2> poses;
  for (const CarmenScan& s : log.scans) poses.push_back(s.pose);
  return poses;
}

std::vector<std::vector<Point2>> ConsistencyReturns(const CarmenLog& log) {
  std::vector<std::vector<Point2>> returns;
  returns.reserve(log.scans.size());
  for (const CarmenScan& s : log.scans)
    returns.push_back(ScanReturns(s.ranges, s.angle_min, s.angle_increment, s.no_return_range(), kConsistencyReach));
  return returns;
}

int Consistency(const CarmenLog& log, const std::string& trajectory, int scan, const std::string& out) {
  const std::vector<Pose2> poses = trajectory.empty() ? LogPoses(log) : ReadTumTrajectory(trajectory, "--trajectory");
  if (poses.size() != log.scans.size())
    throw std::runtime_error("--trajectory: " + std::to_string(poses.size()) + " poses for the log's " +
                             std::to_string(log.scans.size()) + " scans");
  // Searching for one scan's place, its returns look for lines twice as far and count up to 10 cm
  // off: a scan placed tens of centimetres and degrees off (a corrected log's error) has few of
  // its returns within the measure's 15 cm of a line, and the search would see no slope to its
  // place.
  mapping::ScanConsistencyOptions options;
  if (scan >= 0) {
    options.neighbour_radius = 0.3;
    options.cap = 0.1;
  }
  const mapping::ScanConsistency consistency(poses, ConsistencyReturns(log), options);
  const char* at = trajectory.empty() ? "the log's poses" : trajectory.c_str();
  if (scan >= 0) {
    if (scan >= static_cast<int>(poses.size()))
      throw std::runtime_error("--scan: the log has scans 0 to " + std::to_string(poses.size() - 1) + ", not " +
                               std::to_string(scan));
    // The best fit among the poses where at least as many of its returns find a line as at its own,
    // less a fifth: a pose that moves the scan off the walls it saw would be judged on the few
    // returns left.
    const Pose2& own = poses[scan];
    const mapping::ScanConsistency::ScanFit here = consistency.ScanAt(scan, own);
    if (here.scored == 0)
      throw std::runtime_error("--scan: no return of scan " + std::to_string(scan) +
                               " lies on a line the other scans draw at " + at);
    mapping::ScanConsistency::ScanFit best = here;
    Pose2 offset;
    for (int a = -12; a <= 12; ++a)
      for (int i = -4; i <= 4; ++i)
        for (int j = -4; j <= 4; ++j) {
          const Pose2 moved{0.05 * i, 0.05 * j, 0.02 * a};
          const auto fit = consistency.ScanAt(scan, {own.x + moved.x, own.y + moved.y, own.theta + moved.theta});
          if (fit.scored >= 0.8 * here.scored && fit.mean_distance < best.mean_distance) {
            best = fit;
            offset = moved;
          }
        }
    WriteFileAtomically(
        out, "# scan dx_m dy_m dtheta_rad mean_distance_mm own_mean_distance_mm\n" + std::to_string(scan) + " " +
                 std::to_string(offset.x) + " " + std::to_string(offset.y) + " " + std::to_string(offset.theta) + " " +
                 std::to_string(1e3 * best.mean_distance) + " " + std::to_string(1e3 * here.mean_distance) + "\n");
    std::printf(
        "consistency: scan %d at %s: %.2f mm from the other scans' lines, %.2f mm at its best, %+.2f m, "
        "%+.2f m, %+.2f rad from it (map frame) -> %s\n",
        scan, at, 1e3 * here.mean_distance, 1e3 * best.mean_distance, offset.x, offset.y, offset.theta, out.c_str());
    return 0;
  }
  const mapping::ScanConsistencyResult result = consistency.Score();
  std::string table = "# scan stamp returns_scored mean_distance_mm\n";
  for (size_t i = 0; i < poses.size(); ++i) {
    char line[96];
    std::snprintf(line, sizeof line, "%zu %.6f %d %.2f\n", i, log.scans[i].timestamp, result.scan_scored[i],
                  1e3 * result.scan_mean_distance[i]);
    table += line;
  }
  WriteFileAtomically(out, table);
  std::printf("consistency: %zu scans at %s, %lld returns scored, %.2f mm from the lines the other scans draw -> %s\n",
              poses.size(), at, result.scored, 1e3 * result.mean_distance, out.c_str());
  return 0;
}

}  // namespace navd::replay
