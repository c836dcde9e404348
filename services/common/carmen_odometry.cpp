#include "services/common/carmen_odometry.h"

#include <algorithm>
#include <cmath>
#include <cctype>
#include <cstdio>
#include <exception>

#include "services/common/error.h"

namespace navd {

namespace {

// The robot centre's odometry at each scan.
std::vector<Pose2> CentreOdometryAtScans(const CarmenLog& log, const OdometryPairing& pairing) {
  std::vector<const CarmenOdometry*> stamped;
  for (const CarmenOdometry& o : log.odometry)
    if (o.timestamp > 0.0) stamped.push_back(&o);
  std::vector<Pose2> out;
  out.reserve(log.scans.size());
  if (stamped.empty()) {
    for (const CarmenScan& s : log.scans) out.push_back(s.odometry);
    return out;
  }
  // Both lists are in file order: walk them together. nexts[i]: the first stamped line after scan i.
  std::vector<size_t> nexts(log.scans.size());
  for (size_t i = 0, next = 0; i < log.scans.size(); ++i) {
    while (next < stamped.size() && stamped[next]->line < log.scans[i].line) ++next;
    nexts[i] = next;
  }
  for (size_t i = 0; i < log.scans.size(); ++i) {
    const CarmenScan& s = log.scans[i];
    const size_t next = nexts[i];
    const CarmenOdometry* before = next > 0 ? stamped[next - 1] : nullptr;
    const CarmenOdometry* after = next < stamped.size() ? stamped[next] : nullptr;
    // Scans sharing their two lines (a laser faster than the odometry) would all take one pose.
    const bool shared = (i > 0 && nexts[i - 1] == next) || (i + 1 < nexts.size() && nexts[i + 1] == next);
    if (!pairing.by_stamp && !shared && before && after && after->timestamp - before->timestamp <= pairing.max_gap) {
      out.push_back(Interpolate(before->pose, after->pose, pairing.position));
    } else if (before && after && before->timestamp <= s.timestamp && s.timestamp <= after->timestamp &&
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

std::string Describe(const OdometryPairing& pairing) {
  if (pairing.by_stamp) return "by stamp";
  char text[64];
  std::snprintf(text, sizeof text, "at %.2f of the way to the next ODOM line", pairing.position);
  return text;
}

std::optional<OdometryPairing> ParseOdometryPairing(const std::string& text, const std::string& field) {
  if (text == "auto") return std::nullopt;
  if (text == "stamp") return OdometryPairing{};
  size_t used = 0;
  double position = -1.0;
  try {
    position = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || std::isspace(static_cast<unsigned char>(text[0])) ||
      !(position >= 0.0 && position <= 1.0))
    throw Error(ErrorCode::kInvalidArgument,
                field + " must be auto, stamp or a share of the way from 0 to 1, not '" + text + "'");
  return OdometryPairing{false, position + 0.0};  // -0 reads as 0
}

bool HasStampedOdometry(const CarmenLog& log) {
  return std::any_of(log.odometry.begin(), log.odometry.end(),
                     [](const CarmenOdometry& o) { return o.timestamp > 0.0; });
}

std::vector<Pose2> OdometryAtScans(const CarmenLog& log, const OdometryPairing& pairing) {
  std::vector<Pose2> out = CentreOdometryAtScans(log, pairing);
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
