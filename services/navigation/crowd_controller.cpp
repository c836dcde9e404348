#include "services/navigation/crowd_controller.h"

#include <algorithm>
#include <cmath>

namespace navd::navigation {

namespace {
// Metres between where the plan has the robot now and where it is that make the plan stale.
constexpr double kStrayed = 0.3;
}  // namespace

void CrowdController::Reset(double v, double w) {
  plan_ = {};
  plan_start_ = -1.0;
  last_ = {v, w};
}

planning::UnicycleState CrowdController::StateAt(double t) const {
  const auto& s = plan_.states;
  if (s.empty()) return {};
  if (t <= s.front().t) return s.front();
  for (size_t i = 1; i < s.size(); ++i) {
    if (t <= s[i].t) {
      const double f = (t - s[i - 1].t) / std::max(s[i].t - s[i - 1].t, 1e-9);
      planning::UnicycleState m = s[i - 1];
      m.x += f * (s[i].x - m.x);
      m.y += f * (s[i].y - m.y);
      m.yaw = NormalizeAngle(m.yaw + f * NormalizeAngle(s[i].yaw - m.yaw));
      m.v += f * (s[i].v - m.v);
      m.w += f * (s[i].w - m.w);
      m.t = t;
      return m;
    }
  }
  // Past the plan's end: stand.
  planning::UnicycleState end = s.back();
  end.v = end.w = 0.0;
  return end;
}

UnicycleCommand CrowdController::HoldTurn(const Pose2& pose, UnicycleCommand command,
                                          const std::vector<planning::MovingBody>& people) const {
  for (const planning::MovingBody& p : people)
    if (Distance(p.position, pose.translation()) - p.radius - o_.planner.robot_radius < o_.no_turn_gap) command.w = 0.0;
  return command;
}

UnicycleCommand CrowdController::Step(const planning::Costmap& costmap, const Pose2& pose,
                                      const std::vector<Point2>& path, const std::vector<planning::MovingBody>& people,
                                      double now) {
  const double since = plan_start_ < 0.0 ? 0.0 : now - plan_start_;
  const bool strayed = !plan_.states.empty() && Distance(StateAt(since).position(), pose.translation()) > kStrayed;
  if (plan_start_ < 0.0 || since >= o_.replan_period - 1e-9 || since < 0.0 || strayed) {
    planning::CrowdRrtRequest request;
    request.start = {pose.x,
                     pose.y,
                     pose.theta,
                     std::clamp(last_.v, 0.0, o_.limits.max_speed),
                     std::clamp(last_.w, -o_.limits.max_yaw_rate, o_.limits.max_yaw_rate),
                     0.0};
    request.goal = planning::VisibleGoal(costmap, pose.translation(), path);
    request.path = path;
    request.people = people;
    request.limits = o_.limits;
    request.seed = ++plans_;
    // What is left of the last plan, from the vertex the robot has reached.
    if (!strayed && plan_start_ >= 0.0 && !plan_.inputs.empty()) {
      const size_t done = static_cast<size_t>(std::max(0.0, std::round(since / o_.planner.step)));
      if (done < plan_.inputs.size())
        request.previous.assign(plan_.inputs.begin() + static_cast<long>(done), plan_.inputs.end());
    }
    plan_ = planning::PlanCrowdRrt(costmap, request, o_.planner);
    plan_start_ = now;
  }
  const planning::UnicycleState s = StateAt(now - plan_start_ + o_.command_lead);
  last_ = HoldTurn(pose, {s.v, s.w}, people);
  return last_;
}

}  // namespace navd::navigation
