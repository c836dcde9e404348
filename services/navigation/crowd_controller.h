#pragma once
// Book chapter 7's model-predictive loop around its crowd RRT (Sec. 8): the robot drives the best
// trajectory of the last plan while the next is planned from where it is; each plan starts from
// what is left of the last one. The chapter executes 2 s of each plan; we replan every
// replan_period (the plans are cheap enough: a few milliseconds for 2000 vertices), from the
// robot's pose and the speeds last commanded, which the robot tracks under its acceleration limits.
// Walkers change their minds every few seconds: replanning at each plan step (0.25 s) rather than
// every 0.5 s cut the street bench's contacts by a third (a shorter period than the plan's step
// replays the last plan out of step with the new tree, and was worse).
// The plan's goal is the point `lookahead` metres along the leg's path, and the path itself is the
// valley of its cost (g1), so the global plan says where to go and the crowd RRT how to get there
// among people. Map frame, metres, radians, seconds.
#include <cmath>
#include <cstdint>
#include <vector>

#include "services/common/pose2.h"
#include "services/planning/crowd_rrt.h"

namespace navd::navigation {

struct CrowdControllerOptions {
  planning::CrowdRrtOptions planner;
  planning::UnicycleLimits limits;
  double replan_period = 0.25;  // s, best a whole number of the planner's steps
  double lookahead = 12.0;      // m along the leg's path
  // m left on the leg: below this the path follower takes the robot the rest of the way (the RRT
  // has no notion of stopping on a point).
  double handover_distance = 1.5;
  double command_lead = 0.1;  // s: the command is the plan's speeds this far ahead
  // rad off the way to the plan's goal: beyond, the path follower turns the robot round. The RRT
  // turns a robot back from any heading it starts with (it prunes only worse ones), so by default
  // it keeps the robot whatever its heading. The follower heads straight back onto the path across
  // the walkers' way (at 1.3 rad, its turns cost the street runs 6 points), and it turns in place:
  // a robot an escape had turned round at 1.5 m/s coasted on for a metre, blind to the walkers
  // (at 2.4 rad, two of three people walking into it in ten navd street runs).
  double max_heading_error = M_PI;
  // m: with someone's rim this near the robot's (as tracked: a laser blob's centre is off by up
  // to 0.1 m), the robot does not turn: a turn slides it along them, and wheel slip nudges it
  // into them (in navsim, a collision). Ours.
  double no_turn_gap = 0.15;
};

// Forward speed and yaw rate.
struct UnicycleCommand {
  double v = 0.0;  // m/s
  double w = 0.0;  // rad/s
};

class CrowdController {
 public:
  explicit CrowdController(const CrowdControllerOptions& options = {}) : o_(options) {}

  // One control step: replans when due (or when the robot strayed from the plan), then returns
  // the plan's command for `now`.
  // path: the leg's path ahead (map frame); its end is the plan's goal.
  UnicycleCommand Step(const planning::Costmap& costmap, const Pose2& pose, const std::vector<Point2>& path,
                       const std::vector<planning::MovingBody>& people, double now);
  // The robot was driven by something else: the next step plans afresh from standstill speeds
  // `v`, `w` (what the robot does now).
  void Reset(double v = 0.0, double w = 0.0);

  const planning::CrowdTrajectory& plan() const { return plan_; }
  uint64_t plans() const { return plans_; }
  const CrowdControllerOptions& options() const { return o_; }

 private:
  // The plan's state at `t` seconds after it started (linear between its vertices).
  planning::UnicycleState StateAt(double t) const;
  // `command` without its turn while someone is against the robot's rim.
  UnicycleCommand HoldTurn(const Pose2& pose, UnicycleCommand command,
                           const std::vector<planning::MovingBody>& people) const;

  CrowdControllerOptions o_;
  planning::CrowdTrajectory plan_;
  double plan_start_ = -1.0;
  UnicycleCommand last_;
  uint64_t plans_ = 0;
};

}  // namespace navd::navigation
