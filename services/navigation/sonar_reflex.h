#pragma once
// Seed 004's reflexive obstacle avoidance (Ugur, hybrid deliberative/reactive control): the sonar
// ring's front half forms five groups, LEFT, FRONT-LEFT, FRONT, FRONT-RIGHT and RIGHT; the group
// whose echo is strongest (nearest) wins outright and sets the orientation of the response
// vector, away from it (FRONT's two sensors choose the side: away from the nearer); the nearest
// echo sets its magnitude in three discrete levels. The navigator's vector (unit length, towards
// its subgoal) and the response are summed: the sum's direction is the heading to steer to, its
// forward part the share of the navigator's speed kept. Without a stimulus the navigator's command
// passes unchanged ("pure navigation"). The seed gives no thresholds or magnitudes; the defaults
// below are navd's, for a 0.4 m robot at 0.5 m/s. Ranges in metres from the rim; angles in
// radians, robot frame (x forward, counter-clockwise).
#include <array>
#include <vector>

#include "services/common/diff_drive.h"

namespace navd::navigation {

enum class SonarGroup { kNone, kLeft, kFrontLeft, kFront, kFrontRight, kRight };
const char* SonarGroupName(SonarGroup group);

struct SonarEcho {
  double angle = 0.0;  // rad: the sensor's mounting direction
  double range = 0.0;  // m from the sensor on the rim to the echo
};

struct SonarReflexOptions {
  bool enabled = true;
  // Groups by mounting angle: FRONT within front_half of straight ahead, FRONT-LEFT/-RIGHT up to
  // diagonal_end, LEFT/RIGHT up to side_end; sensors further back take no part (the seed's reflex
  // "executes when there is a close obstacle ahead").
  double front_half = 20.0 * M_PI / 180.0;
  double diagonal_end = 70.0 * M_PI / 180.0;
  double side_end = 115.0 * M_PI / 180.0;
  // An echo nearer than level_range[k] is a stimulus of level k + 1 (levels 1-3: weak, strong,
  // urgent); its response's magnitude is level_gain[k] times the navigator's vector.
  std::array<double, 3> level_range = {0.70, 0.45, 0.25};
  std::array<double, 3> level_gain = {0.3, 1.0, 3.0};
  // Response orientations for the left-hand groups (the right-hand ones mirror them): a wall on the
  // left pushes right; one ahead pushes right and back, which slows the robot as it turns.
  double side_response = -90.0 * M_PI / 180.0;
  double diagonal_response = -120.0 * M_PI / 180.0;
  double front_response = -135.0 * M_PI / 180.0;
  // navd's addition: an echo the map or the laser accounts for (within explained_tolerance) is left
  // to the planner, which already goes round it at its own margin; the reflex answers what only
  // the sonar finds (glass, things below the laser's plane). false: every echo is a stimulus, as in
  // the seed.
  bool only_unexplained = true;
  double explained_tolerance = 0.15;         // m
  double sensor_cone = 15.0 * M_PI / 180.0;  // rad: a sensor's opening, for that comparison
  // The deliberative half (Nav2's range sensor layer): unexplained echoes within remember_within
  // become obstacle discs in the leg plans for `memory` seconds, so the path goes round what the
  // reflex met rather than back through it. A disc covers the cone's width at its range. (What
  // the front bumper hits is kept as long.)
  double remember_within = 1.5;  // m
  double memory = 30.0;          // s
};

struct ReflexResponse {
  SonarGroup group = SonarGroup::kNone;
  int level = 0;             // 0: no stimulus
  double orientation = 0.0;  // rad, robot frame
  double magnitude = 0.0;    // times the navigator's unit vector
  double range = 0.0;        // m: the winning echo's
};

class SonarReflex {
 public:
  explicit SonarReflex(const SonarReflexOptions& options = {}) : o_(options) {}

  // The group a sensor mounted at `angle` belongs to (kNone: behind).
  SonarGroup GroupOf(double angle) const;
  // Winner-take-all over `stimuli` (the echoes that count). `navigator_bearing` (rad, robot frame)
  // breaks a tie between FRONT's sensors towards the subgoal's side.
  ReflexResponse Respond(const std::vector<SonarEcho>& stimuli, double navigator_bearing) const;
  // The vector sum applied to the navigation behaviour's command: steers to the heading of
  // (navigator + response) with the follower's law dv = k_p * v * heading and keeps the forward
  // share of the sum of the speed. Commands that do not drive forward pass unchanged.
  static WheelSpeeds Blend(const WheelSpeeds& command, double navigator_bearing, const ReflexResponse& response,
                           double k_p, double max_wheel_speed);

  const SonarReflexOptions& options() const { return o_; }

 private:
  SonarReflexOptions o_;
};

}  // namespace navd::navigation
