#include "services/mapping/known_pose_map.h"

#include <cmath>

#include "services/common/scan_reach.h"

namespace navd::mapping {

OccupancyGrid MapFromLogPoses(const CarmenLog& log, const MapperOptions& options,
                              const std::function<void(size_t, size_t)>& progress) {
  Point2 lo(1e18, 1e18), hi(-1e18, -1e18);
  for (const CarmenScan& s : log.scans) {
    const double reach = ScanReachOf(options, s.ranges, s.no_return_range());
    for (size_t i = 0; i < s.ranges.size(); ++i) {
      if (!IsReading(s.ranges[i])) continue;
      const double r = TracedLength(options, s.ranges[i], s.no_return_range(), reach);
      const double a = s.pose.theta + s.angle_min + i * s.angle_increment;
      const Point2 p = s.pose.translation() + r * Point2(std::cos(a), std::sin(a));
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  lo -= Point2(1, 1);
  hi += Point2(1, 1);
  MapperOptions fitted = options;
  fitted.resolution = ResolutionToFit(lo, hi, options.resolution);
  OccupancyGridMapper mapper(lo, hi, fitted);
  for (size_t k = 0; k < log.scans.size(); ++k) {
    const CarmenScan& s = log.scans[k];
    mapper.AddScan(s.pose, s.ranges, s.angle_min, s.angle_increment, s.no_return_range());
    if (progress && ((k + 1) % 100 == 0 || k + 1 == log.scans.size())) progress(k + 1, log.scans.size());
  }
  return mapper.ToGrid();
}

}  // namespace navd::mapping
