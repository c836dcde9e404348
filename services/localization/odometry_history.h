#pragma once
// The recent odometry of a robot, so a scan is matched with the odometry of its own stamp rather
// than whatever arrived last (at 0.5 m/s, 50 ms is 2.5 cm of error). Odom frame, seconds.
#include <deque>

#include "services/localization/localizer.h"

namespace navd::localization {

class OdometryHistory {
 public:
  // Keeps the newest `capacity` readings; a reading older than the newest (time went back, e.g. a
  // replay restarted) clears the history first.
  explicit OdometryHistory(size_t capacity = 64) : capacity_(capacity) {}
  void Add(const OdometryReading& reading);
  bool empty() const { return readings_.empty(); }
  const OdometryReading& latest() const { return readings_.back(); }
  // The odometry pose at `stamp`, interpolated between the readings around it; the oldest or the
  // newest reading outside the span. Requires !empty().
  Pose2 At(double stamp) const;
  // Angular speed (rad/s) over the last `window` seconds; 0 with fewer than two readings.
  double TurnRate(double window) const;

 private:
  size_t capacity_;
  std::deque<OdometryReading> readings_;
};

}  // namespace navd::localization
