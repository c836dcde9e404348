#pragma once
// Seed 000's grid navigation, states 2-5 (Wahde et al., section 4.1.3): a robot that finds itself
// outside the navigation grid gets back onto it with its laser alone. Outside the grid means its
// pose estimate is where no leg can start: in the margin after an avoidance manoeuvre, inside a
// wall after a localisation error, in unknown space. While a sector ahead (width gamma_c, radius
// r_c) holds an obstacle it turns in place (state 4); once the sector is clear it drives straight
// on (state 5). The executive checks between steps whether a leg can start from the pose (state 2).
//
// One addition to the seed: where the nearest grid point is known, the robot drives off only
// within max_bearing of its bearing (and on while within 90 degrees), so it does not drive away
// from the grid into open space. After a whole turn without such a heading, any clear one will do
// (the seed's rule) until it has driven relaxed_distance.
// Map frame; metres, radians, m/s at the wheel rim.
#include <optional>
#include <vector>

#include "services/common/diff_drive.h"
#include "services/common/pose2.h"

namespace navd::navigation {

struct GridReentryOptions {
  double sector_width = 1.0;      // gamma_c, rad: the whole width of the sector that must be clear
  double sector_radius = 0.6;     // r_c, m from the robot's centre
  double forward_speed = 0.15;    // m/s, both wheels (state 5)
  double rotate_speed = 0.08;     // m/s, the wheels with opposite signs (state 4)
  double max_bearing = 0.5;       // rad: how far off the grid's bearing it may drive off
  double relaxed_distance = 0.5;  // m driven on any clear way before the grid's bearing counts again
  double give_up_after = 30.0;    // s outside the grid before the leg fails
};

enum class ReentryState { kIdle = 0, kCheckSector = 3, kRotate = 4, kForward = 5 };
const char* ReentryStateName(ReentryState state);

class GridReentry {
 public:
  explicit GridReentry(const GridReentryOptions& options = {}) : o_(options) {}

  void Start(double now);
  void Stop() { state_ = ReentryState::kIdle; }
  bool active() const { return state_ != ReentryState::kIdle; }
  // Whether it has been outside the grid longer than give_up_after at `now`.
  bool TimedOut(double now) const { return active() && now - started_at_ > o_.give_up_after; }
  ReentryState state() const { return state_; }
  double started_at() const { return started_at_; }

  // One step at `now` (s): `scan` is the last scan's returns in the robot's frame (m); `toward` the
  // nearest point of the grid (map frame), when known. Returns the wheel command.
  WheelSpeeds Step(const Pose2& pose, const std::vector<Point2>& scan, const std::optional<Point2>& toward, double now);

  // True when no point of `scan` (robot frame) lies within `radius` of the origin inside the
  // sector of full width `width` centred on the x axis.
  static bool SectorClear(const std::vector<Point2>& scan, double width, double radius);

  const GridReentryOptions& options() const { return o_; }

 private:
  GridReentryOptions o_;
  ReentryState state_ = ReentryState::kIdle;
  double started_at_ = 0.0;
  double turn_sign_ = 0.0;                 // +1 left, -1 right; 0: not chosen yet
  static constexpr double kStepGap = 0.5;  // s: steps further apart are not consecutive
  double turned_ = 0.0;                    // rad turned since the robot last drove towards the grid
  double last_step_ = -1.0;
  double last_heading_ = 0.0;
  bool any_clear_way_ = false;  // after a whole turn: any clear way, for relaxed_distance
  Point2 relaxed_at_ = Point2::Zero();
};

}  // namespace navd::navigation
