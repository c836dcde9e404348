#include "services/planning/kinodynamic_planner.h"

#include <ompl/base/Goal.h>
#include <ompl/base/OptimizationObjective.h>
#include <ompl/base/PlannerData.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/goals/GoalSampleableRegion.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/control/DirectedControlSampler.h>
#include <ompl/control/SimpleSetup.h>
#include <ompl/control/StatePropagator.h>
#include <ompl/control/planners/rrt/RRT.h>
#include <ompl/control/planners/sst/SST.h>
#include <ompl/control/spaces/RealVectorControlSpace.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>

#include "services/common/error.h"
#include "services/planning/crowd_route.h"
#include "services/planning/grid_astar_planner.h"

namespace navd::planning {
namespace ob = ompl::base;
namespace oc = ompl::control;

namespace {

constexpr double kStep = 0.05;  // s, one Euler step of Eq. 10

void CheckRequest(const KinodynamicRequest& r) {
  const UnicycleLimits& l = r.limits;
  if (!(l.max_speed > 0 && l.max_yaw_rate > 0 && l.max_accel > 0 && l.max_yaw_accel > 0))
    throw Error(ErrorCode::kInvalidArgument,
                "limits: max_speed, max_yaw_rate, max_accel and max_yaw_accel must be > 0");
  if (!(r.time_limit > 0.0 && r.time_limit <= 60.0))
    throw Error(ErrorCode::kInvalidArgument, "time_limit must be in (0, 60] seconds");
  if (!(r.horizon > 0.0 && r.horizon <= 3600.0))
    throw Error(ErrorCode::kInvalidArgument, "horizon must be in (0, 3600] seconds");
  if (!(r.goal_tolerance > 0.0)) throw Error(ErrorCode::kInvalidArgument, "goal_tolerance must be > 0 metres");
  if (!(r.start_speed >= 0.0 && r.start_speed <= l.max_speed))
    throw Error(ErrorCode::kInvalidArgument, "start_speed must be in [0, max_speed]");
}

// The unicycle's state as plain numbers.
struct Unicycle {
  double x, y, yaw, v, w, t;
};

Unicycle Read(const ob::State* s) {
  const auto* c = s->as<ob::CompoundState>();
  const auto* se2 = c->as<ob::SE2StateSpace::StateType>(0);
  const auto* vel = c->as<ob::RealVectorStateSpace::StateType>(1);
  const auto* time = c->as<ob::RealVectorStateSpace::StateType>(2);
  return {se2->getX(), se2->getY(), se2->getYaw(), vel->values[0], vel->values[1], time->values[0]};
}

void Write(const Unicycle& u, ob::State* s) {
  auto* c = s->as<ob::CompoundState>();
  auto* se2 = c->as<ob::SE2StateSpace::StateType>(0);
  se2->setXY(u.x, u.y);
  se2->setYaw(std::remainder(u.yaw, 2.0 * M_PI));
  c->as<ob::RealVectorStateSpace::StateType>(1)->values[0] = u.v;
  c->as<ob::RealVectorStateSpace::StateType>(1)->values[1] = u.w;
  c->as<ob::RealVectorStateSpace::StateType>(2)->values[0] = u.t;
}

// g1 + g2 + c_t at a point and time: the integrand of Eq. 15 (plus our time price).
class CostField {
 public:
  CostField(const Costmap& costmap, const KinodynamicRequest& r, const std::vector<MovingBody>& moving)
      : costmap_(costmap), r_(r), moving_(moving) {}
  double operator()(const Point2& p, double t) const {
    double g = r_.time_weight;
    const CellIndex c = costmap_.grid().CellOf(p);
    if (costmap_.grid().Contains(c)) g += r_.env_weight * costmap_.cost(c) / Costmap::kMaxCost;
    for (const MovingBody& b : moving_)
      if (b.person) g += r_.people_model.Cost(p, b.position + t * b.velocity, b.velocity);
    return g;
  }

 private:
  const Costmap& costmap_;
  const KinodynamicRequest& r_;
  const std::vector<MovingBody>& moving_;
};

class Eq15Objective : public ob::OptimizationObjective {
 public:
  Eq15Objective(const ob::SpaceInformationPtr& si, const CostField& field)
      : ob::OptimizationObjective(si), field_(field) {
    description_ = "book ch. 7 Eq. 15";
  }
  ob::Cost stateCost(const ob::State* s) const override {
    const Unicycle u = Read(s);
    return ob::Cost(field_({u.x, u.y}, u.t));
  }
  // Trapezoid rule over the motion's duration (states carry their time).
  ob::Cost motionCost(const ob::State* a, const ob::State* b) const override {
    const Unicycle p = Read(a), q = Read(b);
    const double dt = std::max(0.0, q.t - p.t);
    return ob::Cost(0.5 * dt * (field_({p.x, p.y}, p.t) + field_({q.x, q.y}, q.t)));
  }

 private:
  const CostField& field_;
};

// The chapter's CalculateControlInput (Eq. 16): a P controller on speed towards the desired speed
// and a PD controller on heading towards the sampled point, each with Gaussian noise (which keeps
// the tree probabilistically complete); the control is held for a random 0.1-0.5 s. Gains and
// noise are ours (the chapter refers to Svenstrup et al. 2010 for them).
class FeedbackSteering : public oc::DirectedControlSampler {
 public:
  explicit FeedbackSteering(const oc::SpaceInformation* si, const UnicycleLimits& limits)
      : oc::DirectedControlSampler(si), l_(limits) {}
  unsigned int sampleTo(oc::Control* control, const ob::State* source, ob::State* dest) override {
    const Unicycle s = Read(source), d = Read(dest);
    UnicycleInput in = SteerTowards({s.x, s.y, s.yaw, s.v, s.w, s.t}, {d.x, d.y}, l_.max_speed, SteeringGains{});
    in.accel += rng_.gaussian(0.0, 0.3 * l_.max_accel);
    in.yaw_accel += rng_.gaussian(0.0, 0.3 * l_.max_yaw_accel);
    in = ClampInput(in, l_);
    double* u = control->as<oc::RealVectorControlSpace::ControlType>()->values;
    u[0] = in.accel;
    u[1] = in.yaw_accel;
    const int steps =
        rng_.uniformInt(static_cast<int>(si_->getMinControlDuration()), static_cast<int>(si_->getMaxControlDuration()));
    return si_->propagateWhileValid(source, control, steps, dest);
  }
  unsigned int sampleTo(oc::Control* control, const oc::Control*, const ob::State* source, ob::State* dest) override {
    return sampleTo(control, source, dest);
  }

 private:
  UnicycleLimits l_;
  ompl::RNG rng_;
};

// The goal disc; goal samples (for the planners' goal bias) are its centre with any heading,
// speed and time, so the tree is drawn towards the goal's position only.
class GoalDisc : public ob::GoalSampleableRegion {
 public:
  GoalDisc(const ob::SpaceInformationPtr& si, const Point2& goal, double tolerance)
      : ob::GoalSampleableRegion(si), goal_(goal), sampler_(si->allocStateSampler()) {
    setThreshold(tolerance);
  }
  double distanceGoal(const ob::State* s) const override {
    const Unicycle u = Read(s);
    return std::hypot(u.x - goal_.x(), u.y - goal_.y());
  }
  void sampleGoal(ob::State* s) const override {
    sampler_->sampleUniform(s);
    Unicycle u = Read(s);
    u.x = goal_.x();
    u.y = goal_.y();
    Write(u, s);
  }
  unsigned int maxSampleCount() const override { return 1u << 30; }

 private:
  Point2 goal_;
  ob::StateSamplerPtr sampler_;
};

// The state space: the SE(2) pose within the grid's bounds, the speeds within the limits and the
// time within the horizon. The nearest-neighbour metric weighs position and heading first; speeds
// and time only break ties between nearby states.
ob::StateSpacePtr UnicycleSpace(const OccupancyGrid& grid, const UnicycleLimits& l, double horizon) {
  auto space = std::make_shared<ob::CompoundStateSpace>();
  auto se2 = std::make_shared<ob::SE2StateSpace>();
  ob::RealVectorBounds xy(2);
  xy.setLow(0, grid.origin().x());
  xy.setHigh(0, grid.origin().x() + grid.size_x());
  xy.setLow(1, grid.origin().y());
  xy.setHigh(1, grid.origin().y() + grid.size_y());
  se2->setBounds(xy);
  auto velocity = std::make_shared<ob::RealVectorStateSpace>(2);
  ob::RealVectorBounds vb(2);
  vb.setLow(0, 0.0);
  vb.setHigh(0, l.max_speed);
  vb.setLow(1, -l.max_yaw_rate);
  vb.setHigh(1, l.max_yaw_rate);
  velocity->setBounds(vb);
  auto time = std::make_shared<ob::RealVectorStateSpace>(1);
  time->setBounds(0.0, horizon);
  space->addSubspace(se2, 1.0);
  space->addSubspace(velocity, 0.1);
  space->addSubspace(time, 0.001);
  return space;
}

// The controls: linear and yaw acceleration within the limits.
std::shared_ptr<oc::RealVectorControlSpace> AccelerationControls(const ob::StateSpacePtr& space,
                                                                 const UnicycleLimits& l) {
  auto controls = std::make_shared<oc::RealVectorControlSpace>(space, 2);
  ob::RealVectorBounds cb(2);
  cb.setLow(0, -l.max_accel);
  cb.setHigh(0, l.max_accel);
  cb.setLow(1, -l.max_yaw_accel);
  cb.setHigh(1, l.max_yaw_accel);
  controls->setBounds(cb);
  return controls;
}

// Eq. 10 by Euler steps; speeds saturate at the robot's limits.
class UnicyclePropagator : public oc::StatePropagator {
 public:
  UnicyclePropagator(const oc::SpaceInformationPtr& si, const UnicycleLimits& limits)
      : oc::StatePropagator(si), l_(limits) {}
  void propagate(const ob::State* from, const oc::Control* control, double duration, ob::State* result) const override {
    const double* u = control->as<oc::RealVectorControlSpace::ControlType>()->values;
    const Unicycle s0 = Read(from);
    UnicycleState s{s0.x, s0.y, s0.yaw, s0.v, s0.w, s0.t};
    for (double done = 0.0; done < duration - 1e-9; done += kStep) {
      s = Propagate(s, {u[0], u[1]}, std::min(kStep, duration - done), l_);
    }
    Write({s.x, s.y, s.yaw, s.v, s.w, s.t}, result);
  }

 private:
  UnicycleLimits l_;
};

// A state is valid within the horizon, on the grid, off lethal cells, and clear of every moving
// body where it will be at the state's time (the robot's radius: the costmap's inflation).
class UnicycleValidity : public ob::StateValidityChecker {
 public:
  UnicycleValidity(const ob::SpaceInformationPtr& si, const Costmap& costmap, const std::vector<MovingBody>& moving,
                   double horizon)
      : ob::StateValidityChecker(si), costmap_(costmap), moving_(moving), horizon_(horizon) {}
  bool isValid(const ob::State* state) const override {
    const Unicycle s = Read(state);
    if (s.t > horizon_) return false;
    const OccupancyGrid& grid = costmap_.grid();
    const CellIndex c = grid.CellOf({s.x, s.y});
    if (!grid.Contains(c) || costmap_.IsLethal(c)) return false;
    const double robot_radius = costmap_.options().inflation_radius;
    for (const MovingBody& b : moving_) {
      const Point2 at = b.position + s.t * b.velocity;
      if (std::hypot(s.x - at.x(), s.y - at.y()) < b.radius + robot_radius) return false;
    }
    return true;
  }

 private:
  const Costmap& costmap_;
  const std::vector<MovingBody>& moving_;
  double horizon_;
};

ob::PlannerPtr MakePlanner(const oc::SpaceInformationPtr& si, KinodynamicAlgorithm algorithm) {
  if (algorithm == KinodynamicAlgorithm::kSst) {
    auto sst = std::make_shared<oc::SST>(si);
    sst->setGoalBias(0.1);
    sst->setSelectionRadius(0.3);
    sst->setPruningRadius(0.05);
    return sst;
  }
  auto rrt = std::make_shared<oc::RRT>(si);
  rrt->setGoalBias(0.1);
  return rrt;
}

// A solution path at every propagation step, as plain numbers.
KinodynamicTrajectory TrajectoryOf(oc::PathControl path) {
  path.interpolate();
  KinodynamicTrajectory t;
  for (const ob::State* s : path.getStates()) {
    const Unicycle u = Read(s);
    t.points.emplace_back(u.x, u.y);
    t.yaws.push_back(u.yaw);
    t.speeds.push_back(u.v);
    t.times.push_back(u.t);
  }
  return t;
}

}  // namespace

double TrajectoryCost(const Costmap& costmap, const KinodynamicRequest& request, const std::vector<MovingBody>& moving,
                      const std::vector<Point2>& points, const std::vector<double>& times) {
  const CostField field(costmap, request, moving);
  double cost = 0.0;
  for (size_t i = 1; i < points.size() && i < times.size(); ++i)
    cost += 0.5 * (times[i] - times[i - 1]) * (field(points[i - 1], times[i - 1]) + field(points[i], times[i]));
  return cost;
}

KinodynamicTrajectory PlanKinodynamic(const Costmap& costmap, const KinodynamicRequest& r,
                                      const std::vector<MovingBody>& moving, const StopRequested& stop) {
  static std::once_flag quiet;
  std::call_once(quiet, [] { ompl::msg::setLogLevel(ompl::msg::LOG_ERROR); });
  CheckRequest(r);
  const UnicycleLimits& l = r.limits;
  const ob::StateSpacePtr space = UnicycleSpace(costmap.grid(), l, r.horizon);
  oc::SimpleSetup setup(AccelerationControls(space, l));
  const auto si = setup.getSpaceInformation();
  setup.setStatePropagator(std::make_shared<UnicyclePropagator>(si, l));
  setup.setStateValidityChecker(std::make_shared<UnicycleValidity>(si, costmap, moving, r.horizon));
  si->setPropagationStepSize(kStep);
  si->setMinMaxControlDuration(2, 10);  // 0.1 to 0.5 s per control
  si->setDirectedControlSamplerAllocator(
      [&l](const oc::SpaceInformation* info) { return std::make_shared<FeedbackSteering>(info, l); });

  ob::ScopedState<> start(space);
  Write({r.start.x(), r.start.y(), r.start_yaw, r.start_speed, 0.0, 0.0}, start.get());
  setup.setStartState(start);
  setup.setGoal(std::make_shared<GoalDisc>(si, r.goal, r.goal_tolerance));
  const CostField field(costmap, r, moving);
  setup.setOptimizationObjective(std::make_shared<Eq15Objective>(si, field));
  setup.setPlanner(MakePlanner(si, r.algorithm));
  setup.setup();
  if (!si->isValid(start.get()))
    throw Error(ErrorCode::kInvalidArgument, "start: the robot would touch an obstacle or a person there");

  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(r.time_limit);
  bool cancelled = false;
  const ob::PlannerTerminationCondition ptc([&] {
    if (stop && stop()) cancelled = true;
    return cancelled || std::chrono::steady_clock::now() > deadline;
  });
  KinodynamicTrajectory best;
  best.cost = std::numeric_limits<double>::infinity();
  uint64_t vertices = 0;
  // RRT restarts: each round grows a fresh tree to its first trajectory; the cheapest under Eq. 15
  // is kept (the chapter's "best trajectory" over many random trees). SST and single RRT: one round.
  do {
    setup.clear();
    const ob::PlannerStatus status = setup.solve(ptc);
    ob::PlannerData data(si);
    setup.getPlannerData(data);
    vertices += data.numVertices();
    if (status != ob::PlannerStatus::EXACT_SOLUTION) break;
    KinodynamicTrajectory t = TrajectoryOf(setup.getSolutionPath());
    t.cost = TrajectoryCost(costmap, r, moving, t.points, t.times);
    if (t.cost < best.cost) best = std::move(t);
    ++best.rounds;
  } while (r.algorithm == KinodynamicAlgorithm::kRrtRestarts && !ptc());
  best.tree_size = vertices;
  if (best.points.empty()) {
    if (cancelled)
      throw Error(ErrorCode::kDeadlineExceeded,
                  "kinodynamic planning stopped before reaching the goal: deadline exceeded or cancelled");
    throw Error(ErrorCode::kNotFound, "no path: no trajectory reached the goal within time_limit (" +
                                          std::to_string(vertices) + " tree vertices)");
  }
  return best;
}

std::vector<PlannerOptionSpec> KinodynamicPlanner::options() const {
  return {{"time_limit", 0.5, "seconds of planning (SST improves the trajectory for all of it)"},
          {"algorithm", 0,
           "0: control RRT restarts for time_limit, the lowest Eq. 15 cost kept; 1: SST; 2: control RRT, "
           "first trajectory; 3: the crowd RRT (ch. 7 Algorithm 2) in its MPC loop, rolled out along an "
           "A* route against the people predicted at constant velocity (time_limit bounds it)"},
          {"start_yaw", 0.0, "radians, the robot's heading at the start"},
          {"start_speed", 0.0, "m/s, the robot's speed at the start"},
          {"goal_tolerance", 0.25, "metres: the goal disc the trajectory must enter"},
          {"max_speed", 0.5, "m/s"},
          {"max_yaw_rate", 1.5, "rad/s"},
          {"max_accel", 0.5, "m/s^2 (input u_v bound)"},
          {"max_yaw_accel", 2.0, "rad/s^2 (input u_theta bound)"},
          {"time_weight", 1.0, "cost per second (c_t)"},
          {"interest", 0.0, "people's interest in the robot, 0..1 (weights the attractor)"}};
}

namespace {

// Book ch. 7's crowd RRT in its MPC loop, rolled out to the goal along an A* route.
CellPath PlanCrowdRouteInScene(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                               const KinodynamicRequest& r, const PlanningScene& scene, const StopRequested& stop) {
  CheckRequest(r);
  const CellPath route_cells =
      GridAStarPlanner().Plan(costmap, start, goal, {{"diagonal", 1.0}, {"cost_weight", 1.0}}, stop);
  if (route_cells.cells.empty()) throw Error(ErrorCode::kNotFound, "no route from the start to the goal");
  CrowdRouteRequest c;
  c.start = {r.start.x(), r.start.y(), r.start_yaw, r.start_speed, 0.0, 0.0};
  c.goal = r.goal;
  c.goal_tolerance = r.goal_tolerance;
  for (const CellIndex& cell : route_cells.cells) c.route.push_back(costmap.grid().CellCenter(cell));
  c.route.front() = r.start;
  c.route.back() = r.goal;
  c.people = scene.moving;
  c.limits = r.limits;
  c.max_time = r.horizon;
  CrowdRrtOptions o;
  o.desired_speed = r.limits.max_speed;
  o.robot_radius = costmap.options().inflation_radius;
  o.people.interest = r.people_model.interest;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(r.time_limit);
  const CrowdRoute route =
      PlanCrowdRoute(costmap, c, o, [&] { return (stop && stop()) || std::chrono::steady_clock::now() > deadline; });
  CellPath result;
  result.cells = {start, goal};
  for (const UnicycleState& s : route.states) {
    result.points.push_back(s.position());
    result.speed_limits.push_back(s.v / r.limits.max_speed);
  }
  result.keep_shape = true;
  result.expansions = static_cast<uint64_t>(route.vertices);
  return result;
}

}  // namespace

CellPath KinodynamicPlanner::Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                                  const PlannerOptions& options, const StopRequested& stop) const {
  return PlanInScene(costmap, start, goal, options, {}, stop);
}

CellPath KinodynamicPlanner::PlanInScene(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                                         const PlannerOptions& options, const PlanningScene& scene,
                                         const StopRequested& stop) const {
  KinodynamicRequest r;
  r.start = costmap.grid().CellCenter(start);
  r.goal = costmap.grid().CellCenter(goal);
  r.start_yaw = options.at("start_yaw");
  r.start_speed = options.at("start_speed");
  r.goal_tolerance = options.at("goal_tolerance");
  r.time_limit = options.at("time_limit");
  const double algorithm = options.at("algorithm");
  if (algorithm != 0.0 && algorithm != 1.0 && algorithm != 2.0 && algorithm != 3.0)
    throw Error(ErrorCode::kInvalidArgument,
                "options: 'algorithm' must be 0 (RRT restarts), 1 (SST), 2 (RRT) or 3 (crowd RRT rolled out)");
  r.limits = {options.at("max_speed"), options.at("max_yaw_rate"), options.at("max_accel"),
              options.at("max_yaw_accel")};
  r.time_weight = options.at("time_weight");
  r.people_model.interest = options.at("interest");
  if (!(r.people_model.interest >= 0.0 && r.people_model.interest <= 1.0))
    throw Error(ErrorCode::kInvalidArgument, "options: 'interest' must be in [0, 1]");
  if (!(r.time_weight >= 0.0)) throw Error(ErrorCode::kInvalidArgument, "options: 'time_weight' must be >= 0");
  if (algorithm == 3.0) return PlanCrowdRouteInScene(costmap, start, goal, r, scene, stop);
  r.algorithm = static_cast<KinodynamicAlgorithm>(static_cast<int>(algorithm));
  const KinodynamicTrajectory t = PlanKinodynamic(costmap, r, scene.moving, stop);
  CellPath result;
  result.cells = {start, goal};
  result.points = t.points;
  result.keep_shape = true;  // a dynamically feasible trajectory: no shortcuts
  for (double v : t.speeds) result.speed_limits.push_back(v / r.limits.max_speed);
  result.expansions = t.tree_size;
  return result;
}

}  // namespace navd::planning
