#include "services/navigation/leg_progress.h"

#include <algorithm>

namespace navd::navigation {
namespace {

int CountWithin(const std::vector<Point2>& places, const Point2& at, double radius) {
  return static_cast<int>(
      std::count_if(places.begin(), places.end(), [&](const Point2& p) { return Distance(p, at) <= radius; }));
}

}  // namespace

void LegProgress::StartMission(double remaining, double now) {
  recovery_due_ = false;
  recoveries_.clear();
  contacts_.clear();
  best_remaining_ = remaining;
  best_remaining_at_ = now;
  stopped_since_ = -1.0;
}

void LegProgress::WaypointReached(double now) {
  recoveries_.clear();
  contacts_.clear();
  best_remaining_at_ = now;
}

void LegProgress::Stop(double now) {
  if (stopped_since_ < 0.0) stopped_since_ = now;
}

void LegProgress::Drive(double now) {
  if (stopped_since_ < 0.0) return;
  best_remaining_at_ += now - stopped_since_;
  stopped_since_ = -1.0;
}

bool LegProgress::Progressed(double remaining, bool finishing, double now) {
  if (remaining < best_remaining_ - options_.progress_distance || finishing) {
    best_remaining_ = remaining;
    best_remaining_at_ = now;
    return true;
  }
  return now - best_remaining_at_ <= options_.progress_timeout;
}

int LegProgress::Contact(const Point2& where) {
  contacts_.push_back(where);
  return CountWithin(contacts_, where, options_.contact_radius);
}

bool LegProgress::AllowRecovery(const Point2& where) {
  if (CountWithin(recoveries_, where, options_.recovery_radius) >= options_.max_recoveries) return false;
  recoveries_.push_back(where);
  recovery_due_ = true;
  return true;
}

bool LegProgress::TakeRecovery() {
  const bool due = recovery_due_;
  recovery_due_ = false;
  return due;
}

}  // namespace navd::navigation
