#include "services/navigation/recovery_behaviour.h"

#include <cmath>

namespace navd::navigation {

namespace {
// Metres kept between the rim and what is behind when backing up.
constexpr double kRearMargin = 0.05;
}  // namespace

const char* RecoveryKindName(RecoveryKind kind) {
  switch (kind) {
    case RecoveryKind::kClear: return "clear";
    case RecoveryKind::kBackUp: return "back up";
    case RecoveryKind::kSpin: return "spin";
    case RecoveryKind::kWait: return "wait";
  }
  return "?";
}

RecoveryKind NthRecovery(uint32_t n) {
  constexpr RecoveryKind kOrder[] = {RecoveryKind::kClear, RecoveryKind::kBackUp, RecoveryKind::kSpin,
                                     RecoveryKind::kWait};
  return kOrder[(n == 0 ? 0 : n - 1) % 4];
}

void RecoveryBehaviour::Start(RecoveryKind kind, const Pose2& pose, double now) {
  active_ = true;
  kind_ = kind;
  start_ = pose;
  started_at_ = now;
  last_heading_ = pose.theta;
  turned_ = 0.0;
  steps_ = 0;
}

std::optional<WheelSpeeds> RecoveryBehaviour::Step(const Pose2& pose, double rear_free, double now) {
  if (!active_) return std::nullopt;
  const double elapsed = now - started_at_;
  ++steps_;
  std::optional<WheelSpeeds> command;
  switch (kind_) {
    case RecoveryKind::kClear:
      // One standing step: the leg is replanned on what is left.
      if (steps_ == 1) command = WheelSpeeds{};
      break;
    case RecoveryKind::kBackUp: {
      const double backed = Distance(pose.translation(), start_.translation());
      const double time_limit = 2.0 * o_.back_up_distance / o_.back_up_speed + 1.0;
      if (backed < o_.back_up_distance && elapsed < time_limit && rear_free > kRearMargin &&
          (steps_ > 1 || rear_free >= o_.back_up_distance + kRearMargin)) {
        command = WheelSpeeds{-o_.back_up_speed, -o_.back_up_speed};
      }
      break;
    }
    case RecoveryKind::kSpin: {
      turned_ += std::abs(NormalizeAngle(pose.theta - last_heading_));
      last_heading_ = pose.theta;
      if (turned_ < o_.spin_angle && elapsed < 2.0 * o_.spin_angle / o_.spin_rate + 1.0) {
        const double v = o_.spin_rate * wheel_base_ / 2.0;
        command = WheelSpeeds{-v, v};
      }
      break;
    }
    case RecoveryKind::kWait:
      if (elapsed < o_.wait_time) command = WheelSpeeds{};
      break;
  }
  if (!command) active_ = false;
  return command;
}

}  // namespace navd::navigation
