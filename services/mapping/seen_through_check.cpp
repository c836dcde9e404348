#include "services/mapping/seen_through_check.h"

#include <cmath>

#include "services/common/scan_reach.h"

namespace navd::mapping {

SeenThroughCheck::SeenThroughCheck(const Pose2& pose, const std::vector<float>& ranges, double angle_min,
                                   double angle_increment, double no_return, const SeenThroughOptions& options)
    : o_(options),
      inverse_(pose.inverse()),
      ranges_(ranges),
      angle_min_(angle_min),
      angle_increment_(angle_increment),
      no_return_(no_return) {}

bool SeenThroughCheck::SawThrough(const Point2& place) const {
  if (ranges_.size() < 3 || !(angle_increment_ > 0.0)) return false;
  const Point2 local = inverse_ * place;
  const double distance = local.norm();
  if (distance < o_.min_distance || distance > o_.max_distance) return false;
  const double beam = std::round((std::atan2(local.y(), local.x()) - angle_min_) / angle_increment_);
  const double span = o_.span;
  if (!(beam >= span) || beam > static_cast<double>(ranges_.size()) - 1.0 - span) return false;
  const size_t i = static_cast<size_t>(beam);
  for (size_t j = i - o_.span; j <= i + o_.span; ++j) {
    const double r = ranges_[j];
    if (!IsEcho(r, no_return_) || r < distance + o_.margin) return false;
  }
  return true;
}

}  // namespace navd::mapping
