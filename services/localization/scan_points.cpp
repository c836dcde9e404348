#include "services/localization/scan_points.h"

#include <algorithm>
#include <cmath>

#include "services/common/scan_reach.h"

namespace navd::localization {

bool ScanHeaderIsUsable(const ScanReading& scan) {
  return !scan.ranges.empty() && std::isfinite(scan.angle_min) && std::isfinite(scan.angle_increment) &&
         std::isfinite(scan.range_max) && std::isfinite(scan.range_min) && scan.range_max > scan.range_min;
}

std::string ScanGeometryError(size_t ranges, double angle_min, double angle_max, double angle_increment) {
  if (!std::isfinite(angle_min) || !std::isfinite(angle_max) || !std::isfinite(angle_increment) ||
      angle_increment == 0.0) {
    return "angle_min, angle_max and angle_increment must be finite and angle_increment non-zero";
  }
  if (ranges == 0) return "ranges is empty";
  const double beams = (angle_max - angle_min) / angle_increment + 1.0;
  if (!(beams >= 1.0) || std::abs(beams - static_cast<double>(ranges)) > 1.01) {
    return "ranges has " + std::to_string(ranges) + " beams but angle_min..angle_max / angle_increment gives " +
           std::to_string(static_cast<long>(std::lround(beams)));
  }
  return "";
}

std::vector<ScanBeam> SampleBeams(const ScanReading& scan, int count) {
  std::vector<ScanBeam> beams;
  const size_t n = scan.ranges.size();
  const size_t step = count <= 0 ? 1 : std::max<size_t>(1, n / static_cast<size_t>(count));
  for (size_t i = 0; i < n; i += step) {
    const double r = scan.ranges[i];
    // NaN, -inf and readings under the scanner's minimum or kMinEchoRange (self-hits, glare,
    // error codes) say nothing: no beam. At or beyond range_max (+inf too): a no-return.
    if (!IsReading(r) || r < scan.range_min) continue;
    const bool hit = r < scan.range_max;
    beams.push_back({scan.angle_min + i * scan.angle_increment, hit ? r : scan.range_max, hit});
  }
  return beams;
}

std::vector<Point2> ScanEndPoints(const ScanReading& scan, int count) {
  std::vector<Point2> ends;
  for (const ScanBeam& b : SampleBeams(scan, count)) {
    if (b.hit) ends.emplace_back(b.range * std::cos(b.angle), b.range * std::sin(b.angle));
  }
  return ends;
}

}  // namespace navd::localization
