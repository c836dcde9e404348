#include "services/mapping/seen_through_check.h"

#include <algorithm>
#include <cmath>

#include "services/common/scan_reach.h"

namespace navd::mapping {
namespace {

// Beams either side of the one towards a place: `span` rad at `increment` rad apart, at least the
// next beam each side and at most the whole scan. A span or spacing that is no number, or so fine
// that the count would not fit, judges the whole scan, which then never reads as seen through.
size_t SideBeams(double span, double increment, size_t beams) {
  const double count = span / increment;
  const double whole = std::max(1.0, static_cast<double>(beams));
  return static_cast<size_t>(std::isfinite(count) ? std::clamp(std::round(count), 1.0, whole) : whole);
}

}  // namespace

SeenThroughCheck::SeenThroughCheck(const Pose2& pose, const std::vector<float>& ranges, double angle_min,
                                   double angle_increment, double no_return, const SeenThroughOptions& options)
    : o_(options),
      inverse_(pose.inverse()),
      ranges_(ranges),
      angle_min_(angle_min),
      angle_increment_(angle_increment),
      no_return_(no_return),
      side_(SideBeams(o_.span, angle_increment, ranges.size())),
      whole_turn_(static_cast<double>(ranges.size()) * angle_increment >= 2.0 * M_PI - 0.5 * angle_increment) {}

bool SeenThroughCheck::SawThrough(const Point2& place) const {
  if (ranges_.size() < 3 || !(angle_increment_ > 0.0)) return false;
  const Point2 local = inverse_ * place;
  const double distance = local.norm();
  if (distance < o_.min_distance || distance > o_.max_distance) return false;
  // The bearing from the first beam, counter-clockwise within a turn: a scanner sweeping from 0 to
  // 2π sees a place at a negative bearing as well.
  double bearing = NormalizeAngle(std::atan2(local.y(), local.x()) - angle_min_);
  if (bearing < 0.0) bearing += 2.0 * M_PI;
  const double beam = std::round(bearing / angle_increment_);
  const double n = static_cast<double>(ranges_.size()), side = static_cast<double>(side_);
  // A scanner sweeping a whole turn has beams on either side of its seam; any other, only inside
  // its sweep.
  if (whole_turn_ ? (beam >= n + 0.5 || 2.0 * side + 1.0 > n) : (!(beam >= side) || beam > n - 1.0 - side))
    return false;
  const size_t count = ranges_.size(), i = static_cast<size_t>(beam) % count;
  for (size_t k = 0; k <= 2 * side_; ++k) {
    const double r = ranges_[(i + count - side_ + k) % count];
    if (!IsEcho(r, no_return_) || r < distance + o_.margin) return false;
  }
  return true;
}

}  // namespace navd::mapping
