#include "services/navigation/sensed_obstacles.h"

#include <algorithm>

namespace navd::navigation {

void SensedObstacles::SetScanReturns(std::vector<Point2> returns) {
  std::lock_guard<std::mutex> lock(mutex_);
  returns_ = std::move(returns);
}

bool SensedObstacles::has_scan_returns() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return !returns_.empty();
}

void SensedObstacles::SetLayerCells(std::shared_ptr<const std::vector<Point2>> cells) {
  std::lock_guard<std::mutex> lock(mutex_);
  cells_ = std::move(cells);
}

std::shared_ptr<const std::vector<Point2>> SensedObstacles::layer_cells() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return cells_;
}

std::vector<Point2> SensedObstacles::LocalPoints(const Pose2& pose) const {
  constexpr double kGuardRange = 2.0;  // m
  const Pose2 to_robot = pose.inverse();
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<Point2> local;
  local.reserve(returns_.size());
  for (const Point2& p : returns_) local.push_back(to_robot * p);
  if (cells_) {
    for (const Point2& p : *cells_)
      if (Distance(p, pose.translation()) < kGuardRange) local.push_back(to_robot * p);
  }
  return local;
}

void SensedObstacles::Remember(const Point2& at, double radius, double now) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (Disc& d : discs_) {
    if (Distance(d.position, at) < std::max(d.radius, radius)) {
      if (radius < d.radius) {
        d.position = at;
        d.radius = radius;
      }
      d.seen_at = now;
      return;
    }
  }
  discs_.push_back({at, radius, now});
}

void SensedObstacles::Forget(double now, double memory) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::erase_if(discs_, [&](const Disc& d) { return now - d.seen_at > memory; });
}

void SensedObstacles::ForgetAll() {
  std::lock_guard<std::mutex> lock(mutex_);
  discs_.clear();
}

std::vector<SensedObstacles::Disc> SensedObstacles::discs() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return discs_;
}

}  // namespace navd::navigation
