#include "services/navigation/exploration_goal_record.h"

#include <algorithm>

namespace navd::navigation {

void ExplorationGoalRecord::GivenUp(const Point2& goal) {
  const auto near = [&](const Point2& p) { return Distance(p, goal) < radius_; };
  if (std::any_of(retrying_.begin(), retrying_.end(), near)) {
    done_.push_back(goal);
    return;
  }
  given_up_.push_back(goal);
}

bool ExplorationGoalRecord::RetryGivenUp() {
  if (given_up_.empty()) return false;
  retrying_.insert(retrying_.end(), given_up_.begin(), given_up_.end());
  given_up_.clear();
  return true;
}

std::vector<Point2> ExplorationGoalRecord::Excluded() const {
  std::vector<Point2> excluded = done_;
  excluded.insert(excluded.end(), given_up_.begin(), given_up_.end());
  return excluded;
}

}  // namespace navd::navigation
