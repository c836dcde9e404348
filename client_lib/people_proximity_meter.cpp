#include "client_lib/people_proximity_meter.h"

#include <algorithm>
#include <cmath>

#include "dds/conversions.h"
#include "services/planning/personal_space.h"

namespace navd {

namespace {
// s: a gap in the samples longer than this counts as this long (the simulator was paused).
constexpr double kMaxWeight = 0.2;
}  // namespace

void PeopleProximityMeter::AddWorld(const navsim_msgs::msg::dds_::WorldState_& world) {
  const navsim_msgs::msg::dds_::Body_* robot = nullptr;
  for (const auto& b : world.bodies())
    if (b.kind() == "robot" && b.name() == robot_) robot = &b;
  if (!robot) return;
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& b : world.bodies())
    if (b.kind() == "person") nearest = std::min(nearest, std::hypot(b.x() - robot->x(), b.y() - robot->y()));
  Add(dds::FromTime(world.header().stamp()), nearest);
}

void PeopleProximityMeter::Add(double stamp, double nearest) {
  std::lock_guard<std::mutex> lock(mutex_);
  samples_.emplace_back(stamp, nearest);
}

void PeopleProximityMeter::SetWindow(double from, double to) {
  std::lock_guard<std::mutex> lock(mutex_);
  from_ = from;
  to_ = to;
}

ProximityFigures PeopleProximityMeter::Figures() const {
  std::vector<std::pair<double, double>> s;
  double from, to;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    s = samples_;
    from = from_;
    to = to_;
  }
  std::sort(s.begin(), s.end());
  ProximityFigures f;
  double personal = 0.0, intimate = 0.0;
  for (size_t i = 0; i + 1 < s.size(); ++i) {
    const auto& [stamp, nearest] = s[i];
    if (stamp < from || stamp > to || !std::isfinite(nearest)) continue;
    const double w = std::min(s[i + 1].first - stamp, kMaxWeight);
    if (w <= 0.0) continue;
    f.time += w;
    ++f.samples;
    if (nearest < planning::kPersonalZone) personal += w;
    if (nearest < planning::kIntimateZone) intimate += w;
    f.nearest = std::min(f.nearest, nearest);
  }
  if (f.time > 0.0) {
    f.outside_personal = 1.0 - personal / f.time;
    f.outside_intimate = 1.0 - intimate / f.time;
  }
  return f;
}

}  // namespace navd
