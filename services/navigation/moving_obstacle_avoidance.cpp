#include "services/navigation/moving_obstacle_avoidance.h"

#include <cmath>

namespace navd::navigation {

int MovingObstacleAvoidance::Zone(double bearing) const {
  bearing = NormalizeAngle(bearing);
  if (bearing >= options_.inner_zone) return 1;
  if (bearing >= 0.0) return 2;
  if (bearing > -options_.inner_zone) return 3;
  return 4;
}

void MovingObstacleAvoidance::Enter(AvoidancePhase phase, const Pose2& pose, double now) {
  phase_ = phase;
  phase_start_ = pose.translation();
  phase_since_ = now;
  last_heading_ = pose.theta;
}

void MovingObstacleAvoidance::BeginTurn(const Pose2& pose, double angle, double now) {
  Enter(AvoidancePhase::kTurning, pose, now);
  turn_target_ = angle;
  turned_ = 0.0;
  last_heading_ = pose.theta;
}

void MovingObstacleAvoidance::Start(const Pose2& pose, const Point2& obstacle, const AvoidanceSensing& sensing,
                                    double now, bool touching) {
  const Point2 local = pose.inverse() * obstacle;
  zone_ = Zone(std::atan2(local.y(), local.x()));
  // Away from the obstacle: clockwise when it is on the left (zones 1, 2).
  turn_sign_ = zone_ <= 2 ? -1.0 : 1.0;
  const bool rear_clear = sensing.rear_free >= options_.backup_distance + options_.back_clearance;
  const bool head_on = zone_ == 2 || zone_ == 3;
  // Touching, or beside (not head on): back away when the rear is clear.
  if (rear_clear && (touching || !head_on)) {
    Enter(AvoidancePhase::kBackingUp, pose, now);
  } else if (head_on) {
    // Step aside, away from the obstacle when that side is open, else to the other side (it is
    // nearly ahead: either side lets it by), else back up, else turn anyway.
    const double need = options_.pass_distance + options_.min_clearance;
    auto side_free = [&](double sign) {
      return sensing.free_along ? sensing.free_along(sign * options_.inner_turn) : 0.0;
    };
    const bool away_open = side_free(turn_sign_) >= need;
    if (!away_open && side_free(-turn_sign_) >= need) {
      turn_sign_ = -turn_sign_;
    } else if (!away_open && rear_clear) {
      Enter(AvoidancePhase::kBackingUp, pose, now);
      return;
    }
    BeginTurn(pose, options_.inner_turn, now);
  } else {
    BeginTurn(pose, options_.outer_turn, now);
  }
}

WheelSpeeds MovingObstacleAvoidance::Step(const Pose2& pose, const AvoidanceSensing& sensing, double now) {
  const double travelled = (pose.translation() - phase_start_).norm();
  // Stalled wheels (something the sensors miss) must not keep the behaviour going forever.
  auto overdue = [&](double distance, double speed) { return now - phase_since_ > 2.0 * distance / speed + 1.0; };
  switch (phase_) {
    case AvoidancePhase::kIdle:
    case AvoidancePhase::kWaiting: return {};
    case AvoidancePhase::kBackingUp:
      if (travelled >= options_.backup_distance || overdue(options_.backup_distance, options_.backup_speed)) {
        phase_ = AvoidancePhase::kWaiting;
        return {};
      }
      if (sensing.rear_free < options_.back_clearance) {
        // Something behind after all: turn and pass instead (the seed's fallback).
        BeginTurn(pose, zone_ == 2 || zone_ == 3 ? options_.inner_turn : options_.outer_turn, now);
        return Step(pose, sensing, now);
      }
      {
        // Straight back, holding the heading it started with (the wheels alone drift off it).
        const double omega = -2.0 * NormalizeAngle(pose.theta - last_heading_);
        const double turn = 0.5 * options_.wheel_base * omega;
        return {-options_.backup_speed - turn, -options_.backup_speed + turn};
      }
    case AvoidancePhase::kTurning: {
      turned_ += std::abs(NormalizeAngle(pose.theta - last_heading_));
      last_heading_ = pose.theta;
      if (turned_ >= turn_target_) {
        const double ahead = sensing.free_along ? sensing.free_along(0.0) : 0.0;
        if (ahead >= options_.pass_distance + options_.pass_clearance) {
          Enter(AvoidancePhase::kPassing, pose, now);
          return Step(pose, sensing, now);
        }
        if (turned_ >= options_.max_turn) {
          phase_ = AvoidancePhase::kWaiting;
          return {};
        }
      }
      const double v = options_.turn_speed;
      if (overdue(options_.max_turn * 0.5 * options_.wheel_base, v)) {
        phase_ = AvoidancePhase::kWaiting;
        return {};
      }
      // Something at the rim (the laser's, or the rear sensor's): stand still rather than graze it;
      // an obstacle that waits for the robot gives up sooner or later.
      if (sensing.nearest < options_.turn_clearance || sensing.rear_free < options_.turn_clearance) return {};
      return {-turn_sign_ * v, turn_sign_ * v};
    }
    case AvoidancePhase::kPassing: {
      const double ahead = sensing.free_along ? sensing.free_along(0.0) : 0.0;
      if (travelled >= options_.pass_distance || ahead < options_.pass_clearance ||
          overdue(options_.pass_distance, options_.pass_speed)) {
        phase_ = AvoidancePhase::kWaiting;
        return {};
      }
      return {options_.pass_speed, options_.pass_speed};
    }
  }
  return {};
}

const char* AvoidancePhaseName(AvoidancePhase phase) {
  switch (phase) {
    case AvoidancePhase::kIdle: return "idle";
    case AvoidancePhase::kBackingUp: return "backing up";
    case AvoidancePhase::kTurning: return "turning away";
    case AvoidancePhase::kPassing: return "passing";
    case AvoidancePhase::kWaiting: return "waiting";
  }
  return "?";
}

}  // namespace navd::navigation
