#include "services/mapping/seen_through_check.h"

#include <algorithm>
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
      no_return_(no_return),
      side_(angle_increment > 0.0 ? static_cast<size_t>(std::max(1.0, std::round(o_.span / angle_increment))) : 1) {}

bool SeenThroughCheck::SawThrough(const Point2& place) const {
  if (ranges_.size() < 3 || !(angle_increment_ > 0.0)) return false;
  const Point2 local = inverse_ * place;
  const double distance = local.norm();
  if (distance < o_.min_distance || distance > o_.max_distance) return false;
  const double beam = std::round((std::atan2(local.y(), local.x()) - angle_min_) / angle_increment_);
  const double side = static_cast<double>(side_);
  if (!(beam >= side) || beam > static_cast<double>(ranges_.size()) - 1.0 - side) return false;
  const size_t i = static_cast<size_t>(beam);
  for (size_t j = i - side_; j <= i + side_; ++j) {
    const double r = ranges_[j];
    if (!IsEcho(r, no_return_) || r < distance + o_.margin) return false;
  }
  return true;
}

int64_t SharedPlaces::Key(const Point2& p, int dx, int dy) const {
  return (static_cast<int64_t>(std::floor(p.x() / radius_) + dx) << 32) ^
         static_cast<uint32_t>(static_cast<int32_t>(std::floor(p.y() / radius_) + dy));
}

void SharedPlaces::Add(const Point2& point, int scan) {
  entries_.push_back({Key(point, 0, 0), point, scan});
  sorted_ = false;
}

bool SharedPlaces::SeenByAnother(const Point2& point, int scan) {
  if (!sorted_) {
    std::sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) { return a.cell < b.cell; });
    sorted_ = true;
  }
  auto by_cell = [](const Entry& e, int64_t cell) { return e.cell < cell; };
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy) {
      const int64_t cell = Key(point, dx, dy);
      for (auto it = std::lower_bound(entries_.begin(), entries_.end(), cell, by_cell);
           it != entries_.end() && it->cell == cell; ++it)
        if (it->scan != scan && (it->point - point).squaredNorm() < radius_ * radius_) return true;
    }
  return false;
}

}  // namespace navd::mapping
