#include "services/common/carmen_odometry.h"

#include <algorithm>
#include <cmath>

namespace navd {

namespace {

// The robot centre's odometry at each scan.
std::vector<Pose2> CentreOdometryAtScans(const CarmenLog& log) {
  std::vector<const CarmenOdometry*> stamped;
  for (const CarmenOdometry& o : log.odometry)
    if (o.timestamp > 0.0) stamped.push_back(&o);
  std::vector<Pose2> out;
  out.reserve(log.scans.size());
  if (stamped.empty()) {
    for (const CarmenScan& s : log.scans) out.push_back(s.odometry);
    return out;
  }
  // Both lists are in file order: walk them together.
  size_t next = 0;
  for (const CarmenScan& s : log.scans) {
    while (next < stamped.size() && stamped[next]->line < s.line) ++next;
    const CarmenOdometry* before = next > 0 ? stamped[next - 1] : nullptr;
    const CarmenOdometry* after = next < stamped.size() ? stamped[next] : nullptr;
    if (before && after && before->timestamp <= s.timestamp && s.timestamp <= after->timestamp &&
        after->timestamp > before->timestamp) {
      out.push_back(Interpolate(before->pose, after->pose,
                                (s.timestamp - before->timestamp) / (after->timestamp - before->timestamp)));
    } else if (before &&
               (!after || std::abs(s.timestamp - before->timestamp) <= std::abs(after->timestamp - s.timestamp))) {
      out.push_back(before->pose);
    } else {
      out.push_back(after->pose);
    }
  }
  return out;
}

}  // namespace

std::vector<Pose2> OdometryAtScans(const CarmenLog& log) {
  std::vector<Pose2> out = CentreOdometryAtScans(log);
  const Pose2 scanner(log.front_laser_offset, 0.0, 0.0);
  for (Pose2& p : out) p = p * scanner;
  return out;
}

std::vector<Pose2> NoisyOdometryAtScans(const CarmenLog& log, const OdometryNoise& noise, uint64_t seed) {
  OdometryCorruptor corruptor(noise, seed);
  std::vector<Pose2> out;
  out.reserve(log.scans.size());
  for (const CarmenScan& s : log.scans) out.push_back(corruptor.Next(s.pose));
  return out;
}

}  // namespace navd
