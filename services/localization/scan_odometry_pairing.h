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

  // True while the newest scan, stamped `scan_stamp`, should wait for odometry: the newest
  // reading is older than the scan, and scans have waited less than max_wait since the first tick
  // that held one back (a newer scan taking the held one's place does not start the wait again, so
  // odometry that stays behind the scans holds none of them for longer). Call once per tick with a
  // scan; a false answer ends the wait.
  bool Waits(double scan_stamp, const std::optional<OdometryReading>& newest, WallClock::time_point now);

  // The readings to hand the localiser this tick, in order: the one at the scan's stamp (when a
  // scan is handed on, the newest reading is past it, and nothing later was handed on before),
  // from `odometry_at` (the odometry pose at a stamp, from every reading that arrived), then the
  // newest. Remembers the latest stamp handed on (forgotten when the odometry's clock goes back: a
  // replay or a simulator started again).
  std::vector<OdometryReading> Readings(const std::optional<OdometryReading>& newest, std::optional<double> scan_stamp,
                                        const std::function<std::optional<Pose2>(double)>& odometry_at);

 private:
  WallClock::duration max_wait_;
  std::optional<WallClock::time_point> waiting_since_;           // the first tick that held a scan back
  double handed_on_ = -std::numeric_limits<double>::infinity();  // stamp of the latest reading handed on
};

}  // namespace navd::localization
