#include "services/localization/odometry_history.h"

#include <cmath>

namespace navd::localization {

void OdometryHistory::Add(const OdometryReading& reading) {
  if (!readings_.empty() && reading.stamp < readings_.back().stamp) readings_.clear();
  readings_.push_back(reading);
  while (readings_.size() > capacity_) readings_.pop_front();
}

Pose2 OdometryHistory::At(double stamp) const {
  if (stamp >= readings_.back().stamp) return readings_.back().pose;
  if (stamp <= readings_.front().stamp) return readings_.front().pose;
  size_t i = 1;
  while (readings_[i].stamp < stamp) ++i;
  const OdometryReading& a = readings_[i - 1];
  const OdometryReading& b = readings_[i];
  const double span = b.stamp - a.stamp;
  const double s = span > 0.0 ? (stamp - a.stamp) / span : 1.0;
  const Pose2 d = a.pose.inverse() * b.pose;
  return a.pose * Pose2{s * d.x, s * d.y, s * NormalizeAngle(d.theta)};
}

double OdometryHistory::TurnRate(double window) const {
  if (readings_.size() < 2) return 0.0;
  const OdometryReading& last = readings_.back();
  size_t i = readings_.size() - 1;
  while (i > 0 && last.stamp - readings_[i - 1].stamp <= window) --i;
  if (i == readings_.size() - 1) --i;  // at least the last two readings
  const double span = last.stamp - readings_[i].stamp;
  return span > 0.0 ? NormalizeAngle(last.pose.theta - readings_[i].pose.theta) / span : 0.0;
}

}  // namespace navd::localization
