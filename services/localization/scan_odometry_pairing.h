#pragma once
// Hands a localiser each scan with the odometry of its own instant. Scans and odometry come on
// separate streams (two DDS topics), so a scan can arrive before the odometry of its stamp: it
// waits, up to max_wait of wall time, rather than be weighed at a pose the robot has since left
// (at a fast turn that pose is off by a tenth of a radian, and the fit falls as if the robot were
// lost). And a control loop hands on one odometry reading per tick; the reading at the scan's
// stamp, from every reading that arrived, goes in first, so the localiser's prediction to the
// scan does not interpolate across a bend. Stamps in seconds (the odometry's clock).
#include <chrono>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "services/localization/localizer.h"

namespace navd::localization {

class ScanOdometryPairing {
 public:
  using WallClock = std::chrono::steady_clock;
  explicit ScanOdometryPairing(WallClock::duration max_wait = std::chrono::milliseconds(50)) : max_wait_(max_wait) {}

  // True while a scan stamped `scan_stamp`, arrived at `arrival`, should wait for odometry: the
  // newest reading is older than the scan and the wait has not run out.
  bool Waits(double scan_stamp, const std::optional<OdometryReading>& newest, WallClock::time_point arrival,
             WallClock::time_point now) const;

  // The readings to hand the localiser this tick, in order: the one at the scan's stamp (when a
  // scan is handed on, the newest reading is past it, and nothing later was handed on before),
  // from `odometry_at` (the odometry pose at a stamp, from every reading that arrived), then the
  // newest. Remembers the latest stamp handed on.
  std::vector<OdometryReading> Readings(const std::optional<OdometryReading>& newest, std::optional<double> scan_stamp,
                                        const std::function<std::optional<Pose2>(double)>& odometry_at);

 private:
  WallClock::duration max_wait_;
  double handed_on_ = -std::numeric_limits<double>::infinity();  // stamp of the latest reading handed on
};

}  // namespace navd::localization
