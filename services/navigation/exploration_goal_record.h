#pragma once
// The frontier goals an exploration has finished with, and which of them may be tried again.
// A goal reached is done for good (the robot looked at that frontier). A goal given up (no path
// on the costmap at that moment, a failed mission, no progress) is often given up for a passing
// reason: a wall drawn a few centimetres off before a loop closure moved it, a person in a doorway.
// Such goals are left out until nothing else remains, then tried once more; a goal given up a
// second time is left out for good. Map frame, metres.
#include <vector>

#include "services/common/pose2.h"

namespace navd::navigation {

class ExplorationGoalRecord {
 public:
  // Goals within `radius` of one another are the same goal.
  explicit ExplorationGoalRecord(double radius) : radius_(radius) {}

  void Reached(const Point2& goal) { done_.push_back(goal); }
  void GivenUp(const Point2& goal);
  // When no other frontier is left: the goals given up once become choosable again. False when
  // there were none (every goal left out is out for good).
  bool RetryGivenUp();
  // The goals to leave out now.
  std::vector<Point2> Excluded() const;

 private:
  double radius_;
  std::vector<Point2> done_;      // reached, or given up twice
  std::vector<Point2> given_up_;  // once, not retried yet
  std::vector<Point2> retrying_;  // given up once and choosable again
};

}  // namespace navd::navigation
