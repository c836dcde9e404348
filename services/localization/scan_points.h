#pragma once
// What the scan-based localisers read from a laser scan. Robot frame, metres, radians.
#include <string>
#include <vector>

#include "services/localization/localizer.h"

namespace navd::localization {

// Whether a scan's header can be used at all: some ranges, finite angles, range_max > range_min.
bool ScanHeaderIsUsable(const ScanReading& scan);

// Why a scan's geometry is inconsistent ("" when it is not): non-finite or zero increment, or a
// beam count that disagrees with angle_min..angle_max (LaserScan's fields), naming the fields.
std::string ScanGeometryError(size_t ranges, double angle_min, double angle_max, double angle_increment);

// One beam of a scan: its bearing in the robot frame and its range (a no-return has range_max).
struct ScanBeam {
  double angle = 0.0;
  double range = 0.0;
  bool hit = false;  // an echo short of range_max; else a no-return (range = range_max)
};

// An even subset of about `count` beams (all of them when count <= 0 or the scan has fewer),
// leaving out readings that say nothing (NaN, -inf, under range_min or kMinEchoRange).
std::vector<ScanBeam> SampleBeams(const ScanReading& scan, int count);

// The end points of the returns among an even subset of about `count` beams; no-returns (NaN, inf,
// out of range) are left out, since they mark no surface.
std::vector<Point2> ScanEndPoints(const ScanReading& scan, int count);

}  // namespace navd::localization
