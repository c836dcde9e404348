#include "services/localization/scan_odometry_pairing.h"

namespace navd::localization {

bool ScanOdometryPairing::Waits(double scan_stamp, const std::optional<OdometryReading>& newest,
                                WallClock::time_point now) {
  if (!newest || newest->stamp >= scan_stamp) {
    waiting_since_.reset();
    return false;
  }
  if (!waiting_since_) waiting_since_ = now;
  if (now - *waiting_since_ < max_wait_) return true;
  waiting_since_.reset();
  return false;
}

std::vector<OdometryReading> ScanOdometryPairing::Readings(
    const std::optional<OdometryReading>& newest, std::optional<double> scan_stamp,
    const std::function<std::optional<Pose2>(double)>& odometry_at) {
  std::vector<OdometryReading> out;
  if (!newest) return out;
  if (newest->stamp < handed_on_) handed_on_ = -std::numeric_limits<double>::infinity();  // the clock went back
  if (scan_stamp && *scan_stamp > handed_on_ && *scan_stamp < newest->stamp) {
    // The scan's instant carried back from the newest reading by the motion the history holds
    // between them, so the two agree even where the history has taken out a jump.
    const std::optional<Pose2> at_scan = odometry_at(*scan_stamp), at_newest = odometry_at(newest->stamp);
    if (at_scan && at_newest)
      out.push_back({newest->pose * (at_newest->inverse() * *at_scan), newest->covariance, *scan_stamp});
  }
  out.push_back(*newest);
  handed_on_ = std::max(handed_on_, newest->stamp);
  return out;
}

}  // namespace navd::localization
