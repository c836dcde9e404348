#include "services/navigation/reported_people.h"

#include <cmath>
#include <utility>

namespace navd::navigation {

void ReportedPeople::Update(const PeopleReport& report, const Pose2& robot, double seen_at) {
  std::vector<TrackedPerson> people;
  std::map<std::string, int> ids;
  for (const ReportedPerson& r : report.people) {
    if (!r.position.allFinite() || !r.velocity.allFinite()) continue;
    TrackedPerson p;
    const auto known = ids_.find(r.name);
    const bool named = !r.name.empty() && !ids.contains(r.name);
    p.id = named && known != ids_.end() ? known->second : next_id_++;
    if (named) ids[r.name] = p.id;
    p.position = robot * r.position;
    p.velocity = Rotate(r.velocity, robot.theta);
    const double speed = p.velocity.norm();
    if (speed > o_.max_speed) p.velocity *= o_.max_speed / speed;
    // The orientation the same person had, filtered on by their velocity now (Eqs. 5-6).
    p.orientation = std::atan2(p.velocity.y(), p.velocity.x());
    p.first_seen = seen_at;
    for (const TrackedPerson& before : people_) {
      if (before.id != p.id) continue;
      p.orientation = FilteredOrientation(before.orientation, p.velocity, o_.min_direction_speed);
      p.first_seen = before.first_seen;
    }
    p.covariance = Eigen::Matrix4d::Zero();  // the reporter's own; none is given
    p.hits = 1;
    p.last_seen = seen_at;
    p.confirmed = true;
    people.push_back(p);
  }
  people_ = std::move(people);
  ids_ = std::move(ids);
}

void ReportedPeople::Reset() {
  people_.clear();
  ids_.clear();
}

std::vector<TrackedPerson> ReportedPeople::People(double now) const {
  std::vector<TrackedPerson> out;
  for (TrackedPerson p : people_) {
    const double age = now - p.last_seen;
    if (age > o_.forget_after) continue;
    if (age > 0.0) p.position += age * p.velocity;
    out.push_back(p);
  }
  return out;
}

}  // namespace navd::navigation
