#pragma once
// Moving-obstacle avoidance (MOA), Wahde et al. (seed 000, section 4.5): the motor behaviour that
// takes over when the danger level of the nearest moving obstacle is high. The region in front of
// the robot is split into four zones by the obstacle's bearing, left to right: 1 (front-left,
// outer), 2 (ahead, left of the heading), 3 (ahead, right), 4 (front-right, outer); 3 and 4 mirror
// 2 and 1. Our reading of Fig. 9:
//   zones 1 and 4 (the obstacle will pass in front): back straight up a set distance when the rear
//     is clear, otherwise turn away from the obstacle by a set angle and drive forward a set
//     distance;
//   zones 2 and 3 (head-on): step aside: turn away by a larger angle (or towards the other side
//     when only that one is open) and drive forward, turning further, up to max_turn, until the
//     way is clear; back up when neither side is open.
// Every move stops when the way ahead (or behind) closes; then the robot stands still awaiting
// de-activation, as in the seed. Robot frame bearings (radians, counter-clockwise), metres, m/s.
#include <functional>

#include "services/common/diff_drive.h"
#include "services/common/pose2.h"

namespace navd::navigation {

struct MovingObstacleAvoidanceOptions {
  double inner_zone = 0.52;       // rad: |bearing| below this is zone 2 or 3
  double backup_distance = 0.40;  // m
  double backup_speed = 0.30;     // m/s, as fast as seed 000's obstacles
  double outer_turn = 0.79;       // rad (45 degrees): zones 1 and 4 without room behind
  double inner_turn = 1.31;       // rad (75 degrees): zones 2 and 3
  double max_turn = 2.6;          // rad: give up turning for a clear way beyond this
  double turn_speed = 0.12;       // m/s of each wheel, opposite signs
  double wheel_base = 0.33;       // m, to time the turns
  double pass_distance = 0.50;    // m
  double pass_speed = 0.25;       // m/s
  // Passing stops this far short of anything ahead: an obstacle may cross the way, and stopping
  // takes the command's latency and the deceleration.
  double pass_clearance = 0.25;  // m
  double min_clearance = 0.10;   // m kept free between the robot's rim and anything in its way
  // Backing up stops this far short of what the rear sensor reads, for the same reasons, and what
  // is behind may be coming closer (a cart at 0.3 m/s and the robot close 15 cm in 0.25 s).
  double back_clearance = 0.25;  // m
  // Closer than this, even turning in place may graze (the wheels never turn perfectly in place,
  // and a cart at 0.3 m/s closes 3 cm between two scans): the robot waits instead.
  double turn_clearance = 0.12;  // m
  // s standing still after a manoeuvre before another one, when the behaviour still has the robot
  double wait_before_retry = 2.0;
};

// What the robot can see around it, from its own sensors.
struct AvoidanceSensing {
  // Free distance (m) from the robot's rim along `bearing`, for a corridor as wide as the robot.
  std::function<double(double bearing)> free_along;
  double rear_free = 0.0;  // m free behind the robot's rim (rear IR and map)
  double nearest = 1e9;    // m from the rim to the nearest thing the laser sees
};

enum class AvoidancePhase { kIdle, kBackingUp, kTurning, kPassing, kWaiting };

class MovingObstacleAvoidance {
 public:
  explicit MovingObstacleAvoidance(const MovingObstacleAvoidanceOptions& options = {}) : options_(options) {}

  // Zone 1..4 of an obstacle at `bearing` (robot frame).
  int Zone(double bearing) const;
  // Begins a manoeuvre away from `obstacle` (map frame) with the robot at `pose` (map frame).
  // `touching`: the obstacle presses the bumper; turning in place could still graze it, so the
  // robot backs straight away first when it can.
  // `now`: seconds; a move that takes more than twice its time plus a second (wheels stalled) ends.
  void Start(const Pose2& pose, const Point2& obstacle, const AvoidanceSensing& sensing, double now,
             bool touching = false);
  // One control step at time `now` (s); returns the wheel speeds.
  WheelSpeeds Step(const Pose2& pose, const AvoidanceSensing& sensing, double now);
  void Stop() { phase_ = AvoidancePhase::kIdle; }

  AvoidancePhase phase() const { return phase_; }
  // The manoeuvre has run its course: the robot stands still.
  bool done() const { return phase_ == AvoidancePhase::kWaiting; }
  int zone() const { return zone_; }
  const MovingObstacleAvoidanceOptions& options() const { return options_; }

 private:
  void BeginTurn(const Pose2& pose, double angle, double now);
  void Enter(AvoidancePhase phase, const Pose2& pose, double now);

  MovingObstacleAvoidanceOptions options_;
  AvoidancePhase phase_ = AvoidancePhase::kIdle;
  int zone_ = 0;
  double turn_sign_ = -1.0;    // -1: clockwise (away from an obstacle on the left)
  double turn_target_ = 0.0;   // rad still to turn at least
  double turned_ = 0.0;        // rad turned so far in this phase
  double last_heading_ = 0.0;  // rad: at the phase's start (backing up), or at the last step (turning)
  Point2 phase_start_ = Point2::Zero();
  double phase_since_ = 0.0;  // s
};

const char* AvoidancePhaseName(AvoidancePhase phase);

}  // namespace navd::navigation
