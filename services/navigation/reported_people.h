#pragma once
// People reported by a detector or tracker outside navd (people_msgs/People on rt/<ns>/people: a
// camera or leg tracker on a real robot, navsim's `people` sensor), used instead of the laser's
// tracks (navd --people-source topic). Each report lists everyone seen at its stamp; they are
// kept as the person tracker keeps its tracks: in the odometry frame, predicted on at constant
// velocity, forgotten forget_after seconds after the last report that listed them, and given
// book chapter 7's β orientation (Eqs. 5-6). Metres, m/s, seconds.
#include <map>
#include <string>
#include <vector>

#include "services/common/pose2.h"
#include "services/navigation/person_tracker.h"

namespace navd::navigation {

struct ReportedPerson {
  std::string name;                  // the reporter's id for the person, stable while it tracks them
  Point2 position = Point2::Zero();  // m, robot frame at the report's stamp
  Point2 velocity = Point2::Zero();  // m/s over the ground, in the robot frame's axes
};

struct PeopleReport {
  double stamp = 0.0;  // s
  std::vector<ReportedPerson> people;
};

class ReportedPeople {
 public:
  // Uses forget_after, max_speed and min_direction_speed of the tracker's options.
  explicit ReportedPeople(const PersonTrackerOptions& options = {}) : o_(options) {}

  // Replaces the people with those of `report`; `robot` is the robot's pose at report.stamp in the
  // frame they are kept in, `seen_at` the report's stamp on the caller's clock (the clock of
  // People()'s `now`, which need not be the reporter's). People with non-finite values are left
  // out; a person without a name, or with one already taken in the report, is someone new.
  void Update(const PeopleReport& report, const Pose2& robot, double seen_at);
  void Reset();
  bool empty() const { return people_.empty(); }

  // The people of the last report, predicted to `now`; none once it is forget_after old.
  std::vector<TrackedPerson> People(double now) const;

 private:
  PersonTrackerOptions o_;
  std::vector<TrackedPerson> people_;
  std::map<std::string, int> ids_;  // names in the last report
  int next_id_ = 1;
};

}  // namespace navd::navigation
