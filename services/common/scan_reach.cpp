#include "services/common/scan_reach.h"

#include <algorithm>
#include <cmath>

namespace navd {

double ScanReach(const std::vector<float>& ranges, double no_return, const ScanReachOptions& o) {
  const double near = std::min(o.near, no_return);
  const auto echoes =
      std::count_if(ranges.begin(), ranges.end(), [&](float r) { return std::isfinite(r) && r > 0.0f && r < near; });
  return echoes < o.min_near_echoes ? std::max(o.near, o.far) : o.near;
}

}  // namespace navd
