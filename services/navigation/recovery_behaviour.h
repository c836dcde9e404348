#pragma once
// The recoveries a stuck robot runs before its leg is replanned (Nav2's recovery behaviours): one
// at a time, each a short open-loop manoeuvre on the pose estimate. Map frame, metres, radians,
// m/s at the wheel rims, seconds of the daemon clock.
#include <optional>

#include "services/common/diff_drive.h"
#include "services/common/pose2.h"
#include "services/navigation/navigator.h"

namespace navd::navigation {

enum class RecoveryKind {
  kClear,   // forget what the tracked obstacles said (the executive clears them), then replan
  kBackUp,  // back straight up, when the rear is free
  kSpin,    // turn in place (the laser sweeps the surroundings, and the localiser sees them)
  kWait,    // stand still (what blocks may move on)
};
const char* RecoveryKindName(RecoveryKind kind);
// The n-th recovery (from 1) of a leg: clear, back up, spin, wait, then again from clear.
RecoveryKind NthRecovery(uint32_t n);

class RecoveryBehaviour {
 public:
  RecoveryBehaviour(const RecoveryOptions& options, double wheel_base) : o_(options), wheel_base_(wheel_base) {}

  void Start(RecoveryKind kind, const Pose2& pose, double now);
  // The command while the recovery runs; nullopt once it has ended (done, or impossible: no room
  // behind to back up). rear_free: metres free behind the robot's rim.
  std::optional<WheelSpeeds> Step(const Pose2& pose, double rear_free, double now);
  void Stop() { active_ = false; }
  bool active() const { return active_; }
  RecoveryKind kind() const { return kind_; }

 private:
  RecoveryOptions o_;
  double wheel_base_;
  bool active_ = false;
  RecoveryKind kind_ = RecoveryKind::kClear;
  Pose2 start_;
  double started_at_ = 0.0;
  double last_heading_ = 0.0;
  double turned_ = 0.0;  // rad, accumulated
  int steps_ = 0;
};

}  // namespace navd::navigation
