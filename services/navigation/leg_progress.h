#pragma once
// Seed 000's progress check on a leg, with Nav2's recovery budget. A leg progresses while the
// distance left on it shrinks by progress_distance within progress_timeout seconds of driving (time
// the robot is held by another behaviour, a pause or stale sensors does not count). When it does
// not, or a bumper is pressed max_contacts times within contact_radius of one place, a recovery is
// due; up to max_recoveries of them within recovery_radius of one place on a leg, after which the
// leg counts as failed. Counts start again at each waypoint. Metres, seconds. Not thread-safe: the
// navigator calls it under its lock.
#include <vector>

#include "services/common/pose2.h"

namespace navd::navigation {

struct LegProgressOptions {
  double progress_distance = 0.05;  // m
  double progress_timeout = 15.0;   // s
  double recovery_radius = 1.0;     // m
  int max_recoveries = 3;
  double contact_radius = 0.3;  // m
  int max_contacts = 3;
};

class LegProgress {
 public:
  explicit LegProgress(const LegProgressOptions& options) : options_(options) {}

  // A mission starts with `remaining` metres on its first leg at `now`: counts and clock anew.
  void StartMission(double remaining, double now);
  // A new path for the leg: the distance is measured anew, not the clock (a leg replanned every
  // second because something too near to plan round lies across it, while a guard holds the
  // robot, would otherwise never be called stuck).
  void NewPath(double remaining) { best_remaining_ = remaining; }
  // A waypoint was reached: the next leg's counts and clock start now.
  void WaypointReached(double now);
  // The robot stands (held, paused, sensors stale) from `now` on; Drive: it drives again.
  void Stop(double now);
  void Drive(double now);
  // Whether the leg progressed by `now` with `remaining` metres left (`finishing`: it only turns
  // to the goal's heading, which is progress); false when progress_timeout passed without.
  bool Progressed(double remaining, bool finishing, double now);
  // The progress clock starts again (after a recovery).
  void RestartClock(double now) { best_remaining_at_ = now; }
  // A bumper pressed at `where`: how many times within contact_radius of it on this leg.
  int Contact(const Point2& where);
  void ForgetContacts() { contacts_.clear(); }
  // A recovery at `where` if the budget allows one (then due until TakeRecovery), else false.
  bool AllowRecovery(const Point2& where);
  bool TakeRecovery();
  void CancelRecovery() { recovery_due_ = false; }

  const LegProgressOptions& options() const { return options_; }

 private:
  LegProgressOptions options_;
  bool recovery_due_ = false;
  std::vector<Point2> recoveries_;  // where recoveries ran on this leg
  std::vector<Point2> contacts_;    // where bumpers were pressed on this leg
  double best_remaining_ = 0.0;     // smallest distance left on this leg so far
  double best_remaining_at_ = 0.0;  // when it was reached
  double stopped_since_ = -1.0;     // < 0 while driving
};

}  // namespace navd::navigation
