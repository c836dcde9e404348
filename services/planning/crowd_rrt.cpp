#include "services/planning/crowd_rrt.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <utility>

#include "services/common/error.h"
#include "services/planning/stop_short_rollout.h"

namespace navd::planning {

namespace {

constexpr double kSubStep = 0.05;           // s: Eq. 10 is integrated this finely within a vertex step
constexpr double kIndexCell = 0.5;          // m: the nearest-vertex grid's cells
constexpr double kIndexMaxHalfSize = 40.0;  // m: the grid reaches no farther from the start
// A robot slower than this (m/s) and more than kTurnOnTheSpot (rad) off the goal's direction is
// offered a turn on the spot, which sets off once the goal is within kSetOff (rad) of its heading.
constexpr double kStanding = 0.2;
constexpr double kTurnOnTheSpot = 0.5;
constexpr double kSetOff = 0.3;

struct Vertex {
  UnicycleState state;
  UnicycleInput input;  // what took the parent here
  int parent = -1;
  double cost = 0.0;       // ∫(g1 + g2) dt from the start
  double potential = 0.0;  // g1 + g2 here
  bool braking = false;
  bool kept = false;     // on what is left of the last plan
  bool arrived = false;  // its way came within the request's goal_tolerance of the goal
};

class CrowdField {
 public:
  CrowdField(const Costmap& costmap, const CrowdRrtRequest& r, const CrowdRrtOptions& o)
      : costmap_(costmap), o_(o), path_(r.path) {
    for (const MovingBody& b : r.people)
      if (Distance(b.position, r.start.position()) <= o.people_range) people_.push_back(b);
    // A robot that passing people pushed into the inflation (lethal for plans, not yet a wall)
    // may move anywhere no nearer the wall than it is, and never within escape_touch of it, so it
    // can get out; elsewhere the inflation holds. Measured from the robot's centre to the walls'
    // cell edges, as the simulator's discs meet walls: from cell centre to cell centre, "no
    // nearer" let it move anywhere in its row of cells, down to touching the wall (the street
    // bench without the tight retry below touched it twice in seed 19).
    const CellIndex start = costmap.grid().CellOf(r.start.position());
    if (costmap.grid().Contains(start) && costmap.IsLethal(start))
      least_wall_distance_ = std::min(WallDistance(r.start.position()), o.robot_radius + o.escape_touch);
    // The same for the map's edge, which is kept as far as a wall (below).
    const double edge = EdgeDistance(r.start.position());
    if (edge < costmap.options().inflation_radius)
      least_edge_distance_ = std::max(0.5 * costmap.grid().resolution(), edge);
  }
  // Whether the robot may be at `p` as far as the map goes.
  bool Allowed(const Point2& p) const {
    const CellIndex c = costmap_.grid().CellOf(p);
    if (!costmap_.grid().Contains(c)) return false;
    // Nothing lies beyond the map's edge, and the simulator's bodies hit it as a wall; at the
    // street's open ends nothing in the map inflates it, and escapes drove the robot's rim past it
    // (navd's street runs, seed 330).
    const double edge = EdgeDistance(p);
    if (edge < costmap_.options().inflation_radius && edge < least_edge_distance_) return false;
    if (!costmap_.IsLethal(c)) return true;
    return std::isfinite(least_wall_distance_) && WallDistance(p) >= least_wall_distance_;
  }
  // g1 + g2 at `p` and time `t`; infinity where the robot may not be (walls, a person's body).
  double operator()(const Point2& p, double t) const {
    if (!Allowed(p)) return kBlocked;
    const CellIndex c = costmap_.grid().CellOf(p);
    double g = o_.env_weight * costmap_.cost(c) / Costmap::kMaxCost;
    if (!path_.empty()) {
      const double d = DistanceToPath(p);
      g += o_.path_weight * d * d;
    }
    for (const MovingBody& b : people_) {
      const Point2 at = b.position + t * b.velocity;
      const double d = Distance(p, at);
      if (d < b.radius + o_.robot_radius + Margin(t, b.velocity.norm())) return kBlocked;
      // Beyond five of the widest sigmas the Gaussians are nothing.
      if (d < 6.0) g += o_.people.Cost(p, at, b.velocity);
    }
    return g;
  }
  // Metres between the robot's rim at `p` and the nearest rim of a person predicted at `t` ahead of
  // a robot heading `yaw` (in its forward half-plane); infinity when nobody is.
  double GapAhead(const Point2& p, double yaw, double t) const {
    const Point2 heading(std::cos(yaw), std::sin(yaw));
    double gap = std::numeric_limits<double>::infinity();
    for (const MovingBody& b : people_) {
      const Point2 at = b.position + t * b.velocity;
      if ((at - p).dot(heading) <= 0.0) continue;
      gap = std::min(gap, Distance(p, at) - b.radius - o_.robot_radius);
    }
    return gap;
  }
  static constexpr double kBlocked = std::numeric_limits<double>::infinity();
  const std::vector<MovingBody>& people() const { return people_; }

  // Metres kept from the disc of a person walking at `speed` (m/s), predicted `t` seconds ahead: the
  // prediction strays more the further they are predicted to walk.
  double Margin(double t, double speed) const {
    return o_.clearance + (speed > o_.walking_speed ? o_.walking_clearance : 0.0) +
           o_.clearance_growth * speed * std::min(t, o_.clearance_growth_time);
  }

 private:
  double DistanceToPath(const Point2& p) const {
    double best = Distance(p, path_.front());
    for (size_t i = 1; i < path_.size(); ++i) {
      const Point2 a = path_[i - 1], ab = path_[i] - a;
      const double f = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-12), 0.0, 1.0);
      best = std::min(best, Distance(p, a + f * ab));
    }
    return best;
  }

  // Metres from `p` to the nearest edge of an obstacle cell; a lethal cell has one within the
  // inflation radius of its centre, so the search stops a cell beyond that.
  double WallDistance(const Point2& p) const {
    const OccupancyGrid& g = costmap_.grid();
    const int reach = static_cast<int>(std::ceil(costmap_.options().inflation_radius / g.resolution())) + 2;
    const CellIndex c = g.CellOf(p);
    double best = std::numeric_limits<double>::infinity();
    for (int y = c.y - reach; y <= c.y + reach; ++y) {
      for (int x = c.x - reach; x <= c.x + reach; ++x) {
        const CellIndex q{x, y};
        if (g.Contains(q) && costmap_.distance(g.Flat(q)) <= 0.0) best = std::min(best, g.DistanceToCell(p, q));
      }
    }
    return best;
  }

  // Metres from `p` to the nearest side of the map's rectangle (negative outside it).
  double EdgeDistance(const Point2& p) const {
    const OccupancyGrid& g = costmap_.grid();
    const Point2 lo = g.origin(), hi = lo + g.resolution() * Point2(g.width(), g.height());
    return std::min({p.x() - lo.x(), hi.x() - p.x(), p.y() - lo.y(), hi.y() - p.y()});
  }

  const Costmap& costmap_;
  const CrowdRrtOptions& o_;
  const std::vector<Point2>& path_;
  std::vector<MovingBody> people_;
  double least_wall_distance_ = std::numeric_limits<double>::infinity();  // m; infinity: lethal is lethal
  double least_edge_distance_ = std::numeric_limits<double>::infinity();  // m; likewise for the map's edge
};

// The vertices the tree may grow from, bucketed on a square grid round the start, so the nearest
// to a target is found among the cells round it rather than by a scan of every vertex (which made
// a plan's cost grow with the square of its size). Exact: the same vertex as the scan, ties to
// the lowest index. A vertex beyond the grid is kept in the border cell it lies past; a target
// beyond it is answered by a scan.
class NearestVertexIndex {
 public:
  NearestVertexIndex(const Point2& centre, double half_size, double cell)
      : origin_(centre - Point2(half_size, half_size)),
        cell_(cell),
        side_(std::max(1, static_cast<int>(std::ceil(2.0 * half_size / cell)))),
        cells_(static_cast<size_t>(side_) * static_cast<size_t>(side_)) {}

  void Add(int index, const Point2& p) {
    cells_[Flat(Clamp(Cell(p.x(), origin_.x())), Clamp(Cell(p.y(), origin_.y())))].push_back(index);
    all_.push_back(index);
  }

  // Index of the added vertex nearest to `target` in the plane; -1 when none was added.
  template <typename PositionOf>
  int Nearest(const Point2& target, const PositionOf& position) const {
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    const auto consider = [&](int i) {
      const double d = (position(i) - target).squaredNorm();
      if (d < best_d || (d == best_d && i < best)) {
        best_d = d;
        best = i;
      }
    };
    const int cx = Cell(target.x(), origin_.x()), cy = Cell(target.y(), origin_.y());
    if (cx < 0 || cy < 0 || cx >= side_ || cy >= side_) {
      for (const int i : all_) consider(i);
      return best;
    }
    for (int ring = 0; ring < side_; ++ring) {
      const auto visit = [&](int x, int y) {
        if (x >= 0 && y >= 0 && x < side_ && y < side_)
          for (const int i : cells_[Flat(x, y)]) consider(i);
      };
      if (ring == 0) {
        visit(cx, cy);
      } else {
        for (int x = cx - ring; x <= cx + ring; ++x) {
          visit(x, cy - ring);
          visit(x, cy + ring);
        }
        for (int y = cy - ring + 1; y <= cy + ring - 1; ++y) {
          visit(cx - ring, y);
          visit(cx + ring, y);
        }
      }
      // Whatever lies in the next ring or beyond is at least `ring` whole cells away.
      const double reach = ring * cell_;
      if (best >= 0 && best_d <= reach * reach) break;
    }
    return best;
  }

 private:
  int Cell(double v, double origin) const { return static_cast<int>(std::floor((v - origin) / cell_)); }
  int Clamp(int c) const { return std::clamp(c, 0, side_ - 1); }
  size_t Flat(int x, int y) const {
    return static_cast<size_t>(y) * static_cast<size_t>(side_) + static_cast<size_t>(x);
  }

  Point2 origin_;
  double cell_;
  int side_;
  std::vector<std::vector<int>> cells_;
  std::vector<int> all_;
};

void Check(bool ok, const std::string& what) {
  if (!ok) throw Error(ErrorCode::kInvalidArgument, what);
}

// Nothing is valid, not even stopping: someone is walking into the robot. Ours: of a fan of
// constant inputs held for escape_time, the best by what the people would do. Someone who walks
// up to a robot stops short of it (people step round what blocks them), so what touches is the
// robot's own motion into someone beside it: each person walks on as predicted until the next
// step would touch the robot, and stands there. A manoeuvre that moves the robot into someone
// (within escape_touch) or into a wall's inflation, during the manoeuvre or the full braking
// after it, loses to any that does not (walls are known exactly: navd's street seed 330 drove
// back up the street at 1.5 m/s into the map's open end); among those, the
// most room kept wins; among those that all touch, the one that touches latest. On the street
// bench 21 of 23 contacts in 100 runs came during escapes, judged by the room alone (the person
// walking on, or standing still where they are): the robot drove on beside someone at its rim.
// With `short_plan` (the tree's best lives less than min_select_time), that plan followed by
// braking is judged first and is kept unless a manoeuvre of the fan does better by the same rule.
CrowdTrajectory Escape(const CrowdField& field, const UnicycleState& root, const CrowdRrtRequest& r,
                       const CrowdRrtOptions& o, const CrowdTrajectory* short_plan = nullptr) {
  CrowdTrajectory out;
  out.escape = true;
  const StopShortOptions stop_short{o.robot_radius, o.escape_touch, kSubStep, o.escape_time};
  const auto allowed = [&field](const Point2& p) { return field.Allowed(p); };
  // One manoeuvre rolled out and judged: driven for escape_time, then full braking to a stop, which
  // must stop short of the walls and of the people as they walk on and stand. Judged over the
  // manoeuvre alone, escapes kept 1.5 m/s towards walkers 1-2 m ahead and could not stop when
  // they came on (street bench, truth-all: seeds 218 and 258).
  // Long enough to stop from the fastest the robot can be after escape_time (not max_speed alone:
  // a limit of 1000 m/s would roll out for minutes).
  const double stop_time =
      std::min(r.limits.max_speed, std::max(root.v, 0.0) + r.limits.max_accel * o.escape_time) / r.limits.max_accel +
      kSubStep;
  const auto judge = [&](const std::function<UnicycleInput(const UnicycleState&)>& input) {
    const auto then_brake = [&](const UnicycleState& s) {
      return s.t - root.t < o.escape_time - 1e-9 ? input(s) : Braking(s, r.limits, o.step);
    };
    StopShortRollout run =
        RollOutStopShort(root, then_brake, o.escape_time + stop_time, field.people(), r.limits, stop_short, allowed);
    // What is driven is the manoeuvre; the braking only had to be possible.
    while (run.states.size() > 1 && run.states.back().t > root.t + o.escape_time + 1e-9) run.states.pop_back();
    return run;
  };
  double best_touch = -1.0, best_room = -std::numeric_limits<double>::infinity();
  if (short_plan) {
    const auto follow = [&](const UnicycleState& s) -> UnicycleInput {
      const size_t i = static_cast<size_t>(std::max(0.0, std::floor((s.t - root.t) / o.step + 1e-9)));
      if (i < short_plan->inputs.size()) return short_plan->inputs[i];
      return Braking(s, r.limits, o.step);
    };
    const StopShortRollout run = judge(follow);
    best_touch = run.touch;
    best_room = run.room;
    out = *short_plan;
  }
  for (const double a : {-1.0, 0.0, 1.0}) {
    for (const double b : {-1.0, -0.5, 0.0, 0.5, 1.0}) {
      const UnicycleInput u{a * r.limits.max_accel, b * r.limits.max_yaw_accel};
      const StopShortRollout run = judge([&u](const UnicycleState&) { return u; });
      // Two that never touch both have touch = inf: compare equal first (inf - inf is NaN).
      const bool same_touch = run.touch == best_touch || std::abs(run.touch - best_touch) <= 1e-9;
      const bool better = (!same_touch && run.touch > best_touch) || (same_touch && run.room > best_room);
      if (better || out.states.empty()) {
        best_touch = run.touch;
        best_room = run.room;
        out.escape = true;
        out.braking = false;
        out.states.clear();
        for (const UnicycleState& s : run.states)
          if (s.t == root.t || std::fmod(s.t + 1e-9, o.step) < kSubStep) out.states.push_back(s);
        out.inputs.assign(out.states.size() - 1, ClampInput(u, r.limits));
      }
    }
  }
  return out;
}

}  // namespace

Point2 VisibleGoal(const Costmap& costmap, const Point2& from, const std::vector<Point2>& path) {
  // From inside the inflation (a robot brushing a wall) nothing is "visible": the path's end then.
  const CellIndex here = costmap.grid().CellOf(from);
  if (!costmap.grid().Contains(here) || costmap.IsLethal(here)) return path.back();
  for (size_t i = 0; i < path.size(); ++i)
    if (!costmap.SegmentFree(from, path[i])) return i == 0 ? path.back() : path[i - 1];
  return path.back();
}

namespace {

// One tree, grown and chosen from (the chapter's Algorithm 1 with our additions); PlanCrowdRrt has
// checked the request and the options. Its vertices are one `step` of the unicycle each under an
// input from the parent, pruned where the field forbids.
class CrowdTree {
 public:
  CrowdTree(const Costmap& costmap, const CrowdRrtRequest& r, const CrowdRrtOptions& o)
      : r_(r),
        o_(o),
        field_(costmap, r, o),
        start_(r.start.position()),
        start_distance_(Distance(start_, r.goal)),
        direction_(start_distance_ > 1e-6 ? std::atan2(r.goal.y() - start_.y(), r.goal.x() - start_.x()) : r.start.yaw),
        axis_(std::cos(direction_), std::sin(direction_)),
        normal_(-axis_.y(), axis_.x()),
        reach_(std::max(o.desired_speed * o.horizon, 1.0)),
        // (e): 0 when off; the robot cannot stop harder than its limit.
        stop_deceleration_(std::min(o.approach_deceleration, r.limits.max_accel)) {
    tree_.reserve(static_cast<size_t>(o.max_nodes) + r.previous.size() + 64);
    root_ = r.start;
    root_.t = 0.0;
    const double here = field_(start_, 0.0);
    tree_.push_back({root_, {}, -1, 0.0, std::isfinite(here) ? here : 0.0, false, false});
    // (a) A robot already deep in someone's space (they walked up to it) may stay that deep on its
    // way out; the braking chain answers to bodies and walls only, so stopping stays a choice.
    ceiling_ = std::max(o.max_potential, std::isfinite(here) ? here : 0.0);
    // (b) A robot that an escape or a bump turned further than 90° from the goal's direction may
    // turn back towards it: only headings worse than where it starts are pruned (ours; the
    // chapter's robot always faces down the street).
    max_heading_error_ = std::max(M_PI / 2.0, std::abs(NormalizeAngle(root_.yaw - direction_)) + 1e-6);
  }

  // The chains every plan starts from, before the random growth.
  void AddChains() {
    // Line 1: what is left of the last plan, replayed from where the robot is now.
    int tip = 0;
    for (const UnicycleInput& u : r_.previous) {
      if ((tip = Extend(tip, u, false, true)) < 0) break;
    }
    // Ours: a braking chain, then standing (speed and yaw rate damped to nought).
    Chain([this](const UnicycleState& s) { return Braking(s, r_.limits, o_.step); }, /*braking=*/true);
    // Ours: a turn on the spot towards the goal, then on towards it. From a standstill the random
    // extensions speed up as they turn, so a robot that passers-by left facing a wall found no way
    // round and stood there.
    if (root_.v < kStanding && std::abs(NormalizeAngle(root_.yaw - direction_)) > kTurnOnTheSpot) {
      Chain(
          [this](const UnicycleState& s) {
            const double off = std::abs(NormalizeAngle(std::atan2(r_.goal.y() - s.y, r_.goal.x() - s.x) - s.yaw));
            return SteerTowards(s, r_.goal, off > kSetOff ? 0.0 : o_.desired_speed, o_.gains);
          },
          /*braking=*/false);
    }
    // Ours: with the goal an end, a chain steered straight at it. The random extensions, noisy at
    // 1.5 m/s, came within a metre of a 0.25 m goal disc and not into it, round after round.
    if (r_.goal_tolerance > 0.0) {
      Chain([this](const UnicycleState& s) { return SteerTowards(s, r_.goal, o_.desired_speed, o_.gains); },
            /*braking=*/false, /*until_arrived=*/true);
    }
  }

  // Lines 2-9: extensions from the vertex nearest a random target (the goal, or a point of the
  // band ahead), with noise on the steering input, until max_nodes.
  void GrowRandomly() {
    // Large enough for every random target and for where the robot can get to within the horizon,
    // within reason: beyond the grid the answers stay exact, only slower.
    const double index_half_size =
        std::min(std::max(1.1 * reach_ + o_.lateral_range, r_.limits.max_speed * o_.horizon) + 1.0, kIndexMaxHalfSize);
    NearestVertexIndex index(start_, index_half_size, kIndexCell);
    for (int i = 0; i < static_cast<int>(tree_.size()); ++i)
      if (Growable(i)) index.Add(i, At(i).state.position());
    std::mt19937_64 rng(r_.seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::normal_distribution<double> noise_v(0.0, o_.speed_noise), noise_w(0.0, o_.yaw_noise);
    // A pruned extension still counts as an attempt, so a boxed-in robot's plan ends.
    const int attempts = 4 * o_.max_nodes;
    for (int k = 0; static_cast<int>(tree_.size()) < o_.max_nodes && k < attempts; ++k) {
      Point2 target = r_.goal;
      if (unit(rng) >= o_.goal_bias) {
        target = start_ + axis_ * (reach_ * (1.1 * unit(rng) - 0.1)) +
                 normal_ * (o_.lateral_range * (2.0 * unit(rng) - 1.0));
      }
      const int nearest = index.Nearest(target, [this](int i) { return At(i).state.position(); });
      if (nearest < 0) break;
      UnicycleInput u = SteerTowards(At(nearest).state, target, o_.desired_speed, o_.gains);
      u.accel += noise_v(rng);
      u.yaw_accel += noise_w(rng);
      const int i = Extend(nearest, u, false);
      if (i >= 0 && Growable(i)) index.Add(i, At(i).state.position());
    }
  }

  // Line 10: the cheapest vertex by Eq. 15, not the newest; early vertices only when nothing else.
  // None at all: an escape.
  CrowdTrajectory Choose() const {
    int chosen = -1;
    double chosen_cost = std::numeric_limits<double>::infinity();
    double latest = 0.0;
    for (size_t i = 1; i < tree_.size(); ++i) latest = std::max(latest, tree_[i].state.t);
    // When no vertex lives min_select_time (everything runs into someone's predicted way), the
    // cheapest of those that stay clear the longest: the cheapest overall is the shortest, which
    // then ends in a stop in front of people who do not stop.
    const double earliest = std::min(o_.min_select_time, latest - o_.step) - 1e-9;
    for (size_t i = 1; i < tree_.size(); ++i) {
      if (tree_[i].state.t < earliest && !tree_[i].arrived) continue;
      const double c = Total(tree_[i]);
      if (c < chosen_cost) {
        chosen_cost = c;
        chosen = static_cast<int>(i);
      }
    }
    CrowdTrajectory out = chosen < 0 ? Escape(field_, root_, r_, o_) : CrowdTrajectory{};
    out.tree_size = static_cast<int>(tree_.size());
    out.pruned = pruned_;
    if (chosen < 0) {
      out.cost = Total(tree_[0]);
      return out;
    }
    out.cost = chosen_cost;
    out.braking = At(chosen).braking;
    out.arrived = At(chosen).arrived;
    for (int i = chosen; i >= 0; i = At(i).parent) {
      out.states.push_back(At(i).state);
      if (i > 0) out.inputs.push_back(At(i).input);
    }
    std::reverse(out.states.begin(), out.states.end());
    std::reverse(out.inputs.begin(), out.inputs.end());
    return out;
  }

 private:
  const Vertex& At(int i) const { return tree_[static_cast<size_t>(i)]; }

  // One vertex step from tree[from] under `u`; returns the new vertex's index, or -1 when pruned.
  int Extend(int from, const UnicycleInput& u, bool braking, bool kept = false) {
    const double limit = braking ? std::numeric_limits<double>::max() : ceiling_;
    const Vertex& parent = At(from);
    UnicycleState s = parent.state;
    // The field is checked at every sub-step: robot and person close at up to 3 m/s, and a vertex
    // step would jump through a person.
    double cost = parent.cost, previous = parent.potential, highest = 0.0;
    bool arrived = parent.arrived;
    const UnicycleInput input = ClampInput(u, r_.limits);
    // (e) spares a vertex braking at half the limit or more.
    const bool guarded = !braking && stop_deceleration_ > 0.0 && input.accel > -0.5 * r_.limits.max_accel;
    for (double done = 0.0; done < o_.step - 1e-9; done += kSubStep) {
      const double dt = std::min(kSubStep, o_.step - done);
      s = Propagate(s, u, dt, r_.limits);
      const double g = field_(s.position(), s.t);
      highest = std::max(highest, g);
      if (!std::isfinite(g) || highest > limit) break;
      // Ours: the shortfall of the speed along the goal's direction from the desired speed, so a
      // plan that dawdles pays for every second of it, not just for the progress it lacks at the end.
      const double shortfall = std::max(0.0, o_.desired_speed - s.v * std::cos(NormalizeAngle(s.yaw - direction_)));
      // (e) Too fast to stop short of someone ahead, and not braking.
      if (guarded && s.v > 0.0 &&
          s.v * s.v > 2.0 * stop_deceleration_ * std::max(0.0, field_.GapAhead(s.position(), s.yaw, s.t))) {
        highest = CrowdField::kBlocked;
        break;
      }
      if (!arrived) cost += 0.5 * dt * (previous + g) + dt * o_.speed_weight * shortfall * shortfall;
      arrived = arrived || (r_.goal_tolerance > 0.0 && Distance(s.position(), r_.goal) <= r_.goal_tolerance);
      previous = g;
    }
    const bool heading_back = std::abs(NormalizeAngle(s.yaw - direction_)) > max_heading_error_ && s.v > 0.0;
    if (!std::isfinite(highest) || highest > limit || heading_back || s.t > o_.horizon + 1e-9) {
      ++pruned_;
      return -1;
    }
    tree_.push_back({s, input, from, cost, previous, braking, kept, arrived});
    return static_cast<int>(tree_.size()) - 1;
  }

  // A chain from the root, `input` of each tip's state, to the horizon (or until a vertex is
  // pruned, or with `until_arrived` until one arrives).
  template <typename Input>
  void Chain(const Input& input, bool braking, bool until_arrived = false) {
    int tip = 0;
    while (tip >= 0 && !(until_arrived && At(tip).arrived) && At(tip).state.t < o_.horizon - 1e-9) {
      const UnicycleState s = At(tip).state;  // a copy: Extend grows the tree under it
      tip = Extend(tip, input(s), braking);
    }
  }

  // Too late for children; the braking chain is a way out, not a place to grow from (trees grown
  // from its end stop first and then set off again).
  bool Growable(int i) const { return At(i).state.t <= o_.horizon - o_.step + 1e-9 && !At(i).braking; }

  // Eq. 15: the way's cost and, short of the goal, the end's (progress and heading), a vertex on
  // the last plan's remains discounted.
  double Total(const Vertex& v) const {
    const double progress = start_distance_ - Distance(v.state.position(), r_.goal);
    const double heading = NormalizeAngle(v.state.yaw - direction_);
    const double end =
        v.arrived ? 0.0 : o_.end_weight * std::exp(o_.end_rate * progress) + o_.heading_weight * std::pow(heading, 4);
    const double cost = v.cost + end;
    return v.kept ? cost * o_.keep_factor : cost;
  }

  const CrowdRrtRequest& r_;
  const CrowdRrtOptions& o_;
  const CrowdField field_;
  const Point2 start_;
  const double start_distance_;
  const double direction_;  // rad, map frame: from the start towards the goal
  const Point2 axis_, normal_;
  const double reach_;  // m: how far ahead random targets lie
  const double stop_deceleration_;
  UnicycleState root_;
  double ceiling_ = 0.0;  // the potential no vertex but the braking chain's may exceed
  double max_heading_error_ = 0.0;
  std::vector<Vertex> tree_;
  int pruned_ = 0;
};

CrowdTrajectory PlanOnce(const Costmap& costmap, const CrowdRrtRequest& r, const CrowdRrtOptions& o) {
  CrowdTree tree(costmap, r, o);
  tree.AddChains();
  tree.GrowRandomly();
  return tree.Choose();
}

}  // namespace

CrowdTrajectory PlanCrowdRrt(const Costmap& costmap, const CrowdRrtRequest& r, const CrowdRrtOptions& o) {
  const UnicycleState& s0 = r.start;
  Check(
      std::isfinite(s0.x) && std::isfinite(s0.y) && std::isfinite(s0.yaw) && std::isfinite(s0.v) && std::isfinite(s0.w),
      "start: every component must be finite");
  Check(r.goal.allFinite(), "goal: must be finite");
  Check(r.goal_tolerance >= 0.0, "goal_tolerance: must not be negative");
  for (const Point2& p : r.path) Check(p.allFinite(), "path: every point must be finite");
  Check(o.max_nodes >= 2 && o.horizon > 0.0 && o.step > 0.0 && o.desired_speed > 0.0 && o.goal_bias >= 0.0 &&
            o.goal_bias <= 1.0,
        "crowd RRT options: max_nodes >= 2, positive horizon, step and desired_speed, goal_bias in [0, 1]");
  Check(o.clearance >= 0.0 && o.clearance_growth >= 0.0 && o.clearance_growth_time >= 0.0 &&
            o.walking_clearance >= 0.0 && o.walking_speed >= 0.0 && o.approach_deceleration >= 0.0,
        "crowd RRT options: clearance, clearance_growth, clearance_growth_time, walking_clearance, "
        "walking_speed and approach_deceleration must not be negative");
  Check(r.limits.max_speed > 0.0 && r.limits.max_accel > 0.0 && r.limits.max_yaw_rate > 0.0 &&
            r.limits.max_yaw_accel > 0.0,
        "limits: every limit must be positive");
  for (const MovingBody& b : r.people)
    Check(b.position.allFinite() && b.velocity.allFinite(), "people: positions and velocities must be finite");

  CrowdTrajectory plan = PlanOnce(costmap, r, o);
  // Nothing lives min_select_time under the grown clearance (a walker heading straight at the
  // robot at speed blocks every way, the braking chain too), so the robot would follow the plan
  // that lives longest, often at full speed, or an escape. Ours: plan again with the clearance
  // not grown (the people's predicted discs kept `clearance` away, as the chapter's prediction
  // has them), and take that plan if it lives min_select_time; the first one otherwise. Street
  // bench (laser, seeds 1-40): 7 collisions to 3, the share outside the personal zone unchanged.
  const double lives = std::min(o.min_select_time, o.horizon - o.step) - 1e-6;
  const auto short_lived = [lives](const CrowdTrajectory& p) { return !p.arrived && p.states.back().t < lives; };
  if (o.clearance_growth > 0.0 && (plan.escape || short_lived(plan))) {
    CrowdRrtOptions tight = o;
    tight.clearance_growth = 0.0;
    CrowdTrajectory retry = PlanOnce(costmap, r, tight);
    if (!retry.escape && !short_lived(retry)) plan = std::move(retry);
  }
  // Still nothing lives min_select_time: the robot would drive the plan that lives longest, often
  // a fraction of a second at speed, into people who (unlike the prediction) stop short of it, and
  // the escape came a few replans later, too late. Ours: judge that plan, with braking after it,
  // as the escapes are, and let the fan replace it. Street bench (laser, seeds 1-150): 15 contacts
  // to 8, the share outside the personal zone up from 97.3-98.0% to 97.6-98.2%.
  if (!plan.escape && short_lived(plan)) {
    const CrowdField field(costmap, r, o);
    UnicycleState root = r.start;
    root.t = 0.0;
    const int tree_size = plan.tree_size, pruned = plan.pruned;
    plan = Escape(field, root, r, o, &plan);
    plan.tree_size = tree_size;
    plan.pruned = pruned;
  }
  return plan;
}

}  // namespace navd::planning
