#pragma once
// The path-following controller of seed 000 (Wahde et al., section 4.1.3, states 7-9): rotate in
// place while the heading error |dphi| exceeds delta, otherwise drive with
//   v_L = V_nav - dV,  v_R = V_nav + dV,  dV = K_p * V_nav * dphi,
// and advance to the next waypoint within d_p of the current one. Two additions keep it precise:
// hysteresis (after a rotation it drives once |dphi| < delta_resume, not just below delta), and a
// braking final approach (v = sqrt(2 a d)) that stops within goal_tolerance of the goal rather than d_p.
// Poses in the map frame; metres, radians, m/s at the wheel rim.
#include <optional>
#include <vector>

#include "services/common/diff_drive.h"
#include "services/common/pose2.h"

namespace navd::navigation {

struct PathFollowerParams {
  double heading_threshold = 0.8;  // delta, rad: rotate in place above this
  double heading_resume = 0.25;    // rad: stop rotating below this
  double v_nav = 0.5;              // V_nav, m/s
  double k_p = 1.0;                // K_p, 1/rad
  // d_p, m: a waypoint counts as reached within this. With waypoints closer than d_p the robot
  // steers towards a point about d_p ahead on the path, which rounds corners instead of stopping.
  double waypoint_radius = 0.35;
  double waypoint_spacing = 0.25;        // d_wp, m: the path is densified to at most this spacing
  double goal_tolerance = 0.05;          // m
  double goal_heading_tolerance = 0.05;  // rad
  double approach_decel = 0.6;           // m/s^2: the final approach slows as sqrt(2 a d)
  double min_speed = 0.04;               // m/s: slowest approach and rotation wheel speed
  double rotate_speed = 0.3;             // m/s: wheel speed when turning in place
  double rotate_gain = 0.6;              // (m/s)/rad: turning slows near the target heading
  double wheel_base = 0.33;              // m
  double max_wheel_speed = 0.5;          // m/s
};

enum class FollowerState { kIdle, kRotating, kDriving, kFinalRotation, kArrived };

struct FollowerCommand {
  WheelSpeeds wheels;
  FollowerState state = FollowerState::kIdle;
};

class PathFollower {
 public:
  explicit PathFollower(const PathFollowerParams& params = {}) : p_(params) {}

  // path: start first, goal last (at least two points). goal_heading: final heading to turn to.
  void SetPath(const std::vector<Point2>& path, std::optional<double> goal_heading);
  void Clear();
  FollowerCommand Step(const Pose2& pose);

  FollowerState state() const { return state_; }
  // Distance left along the path from `pose` through the remaining waypoints, metres.
  double DistanceRemaining(const Pose2& pose) const;
  // Bearing (rad, robot frame) of the waypoint steered to while driving forward; nullopt otherwise.
  std::optional<double> SubgoalBearing(const Pose2& pose) const;
  size_t waypoint_index() const { return index_; }
  size_t waypoint_count() const { return waypoints_.size(); }
  const std::vector<Point2>& waypoints() const { return waypoints_; }
  const PathFollowerParams& params() const { return p_; }
  // While another controller steers along the path (the crowd controller among people), the
  // follower only keeps its place on the path, by the waypoint nearest the robot, and neither
  // stops to rotate nor starts a new path by rotating; its commands are then not driven.
  void SetExternalSteering(bool on) { external_ = on; }
  bool external_steering() const { return external_; }
  // The path from the waypoint steered to on for `distance` metres (to the goal when it ends
  // sooner), map frame; empty without a path.
  std::vector<Point2> PathAhead(double distance) const;

 private:
  WheelSpeeds Rotate(double dphi) const;
  // Moves the target to the farthest waypoint already within reach.
  void SkipReachedWaypoints(const Pose2& pose);
  // Steered off the path by someone else (the crowd controller): moves the target to the waypoint
  // after the one the robot is level with.
  void CatchUpWithSteering(const Pose2& pose);

  PathFollowerParams p_;
  std::vector<Point2> waypoints_;
  std::optional<double> goal_heading_;
  size_t index_ = 0;
  FollowerState state_ = FollowerState::kIdle;
  bool external_ = false;
};

// Inserts points so consecutive ones are at most `spacing` apart (seed 000's d_wp).
std::vector<Point2> DensifyPath(const std::vector<Point2>& path, double spacing);

}  // namespace navd::navigation
