#include "services/common/scan_reach.h"

#include <algorithm>
#include <cmath>

namespace navd {

double ScanReach(const std::vector<float>& ranges, double no_return, const ScanReachOptions& o) {
  const double near = std::min(o.near, no_return);
  const auto echoes = std::count_if(ranges.begin(), ranges.end(), [&](float r) { return IsEcho(r, near); });
  const double needed =
      o.min_near_echoes * std::max(1.0, static_cast<double>(ranges.size()) / static_cast<double>(kSickHalfDegreeBeams));
  return static_cast<double>(echoes) < needed ? std::max(o.near, o.far) : o.near;
}

std::vector<Point2> ScanReturns(const std::vector<float>& ranges, double angle_min, double angle_increment,
                                double no_return, double reach) {
  const double cut = std::min(reach, no_return);
  std::vector<Point2> out;
  out.reserve(ranges.size());
  for (size_t i = 0; i < ranges.size(); ++i) {
    const double r = ranges[i];
    if (!IsEcho(r, cut)) continue;
    const double a = angle_min + static_cast<double>(i) * angle_increment;
    out.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return out;
}

}  // namespace navd
