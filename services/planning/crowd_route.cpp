#include "services/planning/crowd_route.h"

#include <algorithm>
#include <cmath>

#include "services/common/error.h"

namespace navd::planning {

namespace {

constexpr double kStallDistance = 0.1;  // m
constexpr double kStallTime = 10.0;     // s

// The index of the route point nearest `p`, searching forward from `from` (the route is followed,
// not jumped along) within `window` points.
size_t NearestAhead(const std::vector<Point2>& route, const Point2& p, size_t from, size_t window) {
  size_t best = from;
  for (size_t i = from; i < route.size() && i < from + window; ++i)
    if (Distance(route[i], p) < Distance(route[best], p)) best = i;
  return best;
}

// Where the segment a-b first comes within `tolerance` of `goal`, as a fraction of the way from a
// to b; negative when it does not.
double Arrival(const Point2& a, const Point2& b, const Point2& goal, double tolerance) {
  const Point2 ab = b - a;
  const double length2 = ab.squaredNorm();
  if (length2 < 1e-18) return Distance(a, goal) <= tolerance ? 0.0 : -1.0;
  // |a + f ab - goal|² = tolerance²: the smaller root in [0, 1].
  const Point2 ag = a - goal;
  const double half_b = ag.dot(ab), c = ag.squaredNorm() - tolerance * tolerance;
  if (c <= 0.0) return 0.0;
  const double discriminant = half_b * half_b - length2 * c;
  if (discriminant < 0.0) return -1.0;
  const double f = (-half_b - std::sqrt(discriminant)) / length2;
  return f >= 0.0 && f <= 1.0 ? f : -1.0;
}

}  // namespace

CrowdRoute PlanCrowdRoute(const Costmap& costmap, const CrowdRouteRequest& r, const CrowdRrtOptions& o,
                          const StopRequested& stop) {
  if (r.route.size() < 2) throw Error(ErrorCode::kInvalidArgument, "route: needs at least two points");
  if (!(r.goal_tolerance > 0.0)) throw Error(ErrorCode::kInvalidArgument, "goal_tolerance must be > 0 metres");
  if (!(r.execute > 0.0) || !(r.lookahead > 0.0) || !(r.max_time > 0.0))
    throw Error(ErrorCode::kInvalidArgument, "execute, lookahead and max_time must be positive");
  CrowdRoute out;
  UnicycleState robot = r.start;
  robot.t = 0.0;
  out.states.push_back(robot);
  if (Distance(robot.position(), r.goal) <= r.goal_tolerance) return out;
  size_t along = 0;  // the route point the robot is at
  // Where the robot last moved on from, and when: a robot the plans hold still (a goal inside
  // someone's space, a way through a crowd that does not open) is not going to arrive.
  Point2 settled = robot.position();
  double settled_at = 0.0;
  std::vector<UnicycleInput> left;  // what is left of the last plan
  while (true) {
    if (stop && stop()) throw Error(ErrorCode::kDeadlineExceeded, "deadline passed while the crowd RRT rolled out");
    if (Distance(robot.position(), settled) > kStallDistance) {
      settled = robot.position();
      settled_at = robot.t;
    } else if (robot.t - settled_at > kStallTime) {
      throw Error(ErrorCode::kNotFound, "the crowd RRT held the robot still at " + FormatPoint(settled) + " for " +
                                            std::to_string(static_cast<int>(kStallTime)) +
                                            " s: the way on stays inside people's space");
    }
    if (robot.t >= r.max_time)
      throw Error(ErrorCode::kNotFound,
                  "the crowd RRT did not reach the goal within " + std::to_string(static_cast<int>(r.max_time)) + " s");
    along = NearestAhead(r.route, robot.position(), along, 200);
    CrowdRrtRequest round;
    round.start = robot;
    round.start.t = 0.0;
    double ahead = 0.0;
    round.path.push_back(r.route[along]);
    for (size_t i = along + 1; i < r.route.size() && ahead < r.lookahead; ++i) {
      ahead += Distance(r.route[i - 1], r.route[i]);
      round.path.push_back(r.route[i]);
    }
    round.goal = VisibleGoal(costmap, robot.position(), round.path);
    // The route's end in sight: a plan that reaches it ends there (a round that swept past it at
    // speed, a few centimetres wide of the tolerance, came back round for seconds).
    if (round.goal == r.route.back()) round.goal_tolerance = r.goal_tolerance;
    round.people = r.people;
    for (MovingBody& b : round.people) b.position += robot.t * b.velocity;
    round.previous = left;
    round.limits = r.limits;
    round.seed = r.seed + static_cast<uint64_t>(out.plans);
    const CrowdTrajectory plan = PlanCrowdRrt(costmap, round, o);
    ++out.plans;
    out.vertices += plan.tree_size;
    // Keep the first `execute` seconds; stop where the goal disc is entered.
    size_t kept = 0;
    for (size_t i = 1; i < plan.states.size() && plan.states[i].t <= r.execute + 1e-9; ++i) {
      UnicycleState s = plan.states[i];
      const UnicycleState& before = plan.states[i - 1];
      const double f = Arrival(before.position(), s.position(), r.goal, r.goal_tolerance);
      if (f >= 0.0) {
        s.x = before.x + f * (s.x - before.x);
        s.y = before.y + f * (s.y - before.y);
        s.v = before.v + f * (s.v - before.v);
        s.t = before.t + f * (s.t - before.t);
        s.t += robot.t;
        out.states.push_back(s);
        return out;
      }
      s.t += robot.t;
      out.states.push_back(s);
      kept = i;
    }
    if (kept == 0) {
      throw Error(ErrorCode::kNotFound, "the crowd RRT found no way on from " + FormatPoint(robot.position()));
    }
    robot = out.states.back();
    left.assign(plan.inputs.begin() + static_cast<long>(std::min(kept, plan.inputs.size())), plan.inputs.end());
  }
}

}  // namespace navd::planning
