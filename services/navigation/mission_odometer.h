#pragma once
// What a mission has driven: the distance the pose estimate travelled and the time the navigation
// behaviour drove, for the feedback's distance_travelled, a mission's max_distance and the ETA's
// speed. Map frame, metres, seconds of the daemon clock. Not thread-safe: the navigator's lock
// guards it.
#include "services/common/pose2.h"

namespace navd::navigation {

class MissionOdometer {
 public:
  // A new mission starts at `pose` at time `now`: nothing driven yet.
  void Start(const Pose2& pose, double now);
  // The estimate is `pose` at `now`; `moving`: the navigation behaviour drove since the last call.
  // Outside a mission (`counting` false) nothing is booked, but the next step starts from here.
  void Step(const Pose2& pose, double now, bool moving, bool counting);

  double distance() const { return distance_; }        // m
  double moving_time() const { return moving_time_; }  // s

 private:
  // Distance is booked in chords of at least kChord: summing every control step's displacement
  // would also sum the estimate's millimetre jitter (about 1 % over 100 m). An estimate that jumps
  // farther than kMaxStep in one step was re-anchored (set-pose, relocalisation): not travel.
  static constexpr double kChord = 0.05;   // m
  static constexpr double kMaxStep = 0.5;  // m

  Point2 anchor_{0.0, 0.0};  // where distance was last booked
  double distance_ = 0.0;
  double moving_time_ = 0.0;
  double last_step_ = -1.0;  // < 0 before the first step
};

}  // namespace navd::navigation
