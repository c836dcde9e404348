#include "services/planning/ompl_planner.h"

#include <ompl/base/MotionValidator.h>
#include <ompl/base/PlannerData.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/spaces/DubinsStateSpace.h>
#include <ompl/base/spaces/ReedsSheppStateSpace.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/geometric/planners/prm/PRMstar.h>
#include <ompl/geometric/planners/rrt/InformedRRTstar.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/Console.h>

#include <chrono>
#include <cmath>
#include <mutex>

#include "services/common/error.h"
#include "services/common/grid_traversal.h"

namespace navd::planning {
namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace {

// Straight SE(2) motions checked exactly with the costmap's cell traversal (the same test as every
// other planner's line of sight), instead of OMPL's sampling, which can step over a cell corner.
class SegmentMotionValidator : public ob::MotionValidator {
 public:
  SegmentMotionValidator(const ob::SpaceInformationPtr& si, const Costmap& costmap)
      : ob::MotionValidator(si), costmap_(costmap) {}

  bool checkMotion(const ob::State* a, const ob::State* b) const override {
    if (!si_->isValid(b)) {
      ++invalid_;
      return false;
    }
    const bool ok = costmap_.SegmentFree(XY(a), XY(b));
    ++(ok ? valid_ : invalid_);
    return ok;
  }

  bool checkMotion(const ob::State* a, const ob::State* b, std::pair<ob::State*, double>& last_valid) const override {
    const Point2 p = XY(a), q = XY(b);
    const double length = (q - p).norm();
    double blocked_at = -1.0;
    TraverseSegment(costmap_.grid(), p, q, [&](const CellIndex& c, double t) {
      if (costmap_.grid().Contains(c) && !costmap_.IsLethal(c)) return true;
      blocked_at = t;
      return false;
    });
    if (blocked_at < 0) {
      ++valid_;
      return true;
    }
    ++invalid_;
    const double fraction = length > 0 ? std::max(0.0, (blocked_at - 1e-6) / length) : 0.0;
    if (last_valid.first) si_->getStateSpace()->interpolate(a, b, fraction, last_valid.first);
    last_valid.second = fraction;
    return false;
  }

 private:
  static Point2 XY(const ob::State* s) {
    const auto* se2 = s->as<ob::SE2StateSpace::StateType>();
    return {se2->getX(), se2->getY()};
  }
  const Costmap& costmap_;
};

}  // namespace

std::string OmplPlanner::name() const {
  switch (algorithm_) {
    case Algorithm::kRrtConnect: return "rrt_connect";
    case Algorithm::kRrtStar: return "rrt_star";
    case Algorithm::kPrmStar: return "prm_star";
    case Algorithm::kInformedRrtStar: return "informed_rrt_star";
    case Algorithm::kBitStar: return "bit_star";
  }
  return "ompl";
}

std::string OmplPlanner::description() const {
  switch (algorithm_) {
    case Algorithm::kRrtConnect: return "OMPL RRT-Connect in SE(2)/Dubins/Reeds-Shepp (first solution, simplified)";
    case Algorithm::kRrtStar: return "OMPL RRT* (asymptotically optimal, runs for time_limit)";
    case Algorithm::kPrmStar: return "OMPL PRM* (asymptotically optimal roadmap, runs for time_limit)";
    case Algorithm::kInformedRrtStar: return "OMPL Informed RRT* (runs for time_limit)";
    case Algorithm::kBitStar: return "OMPL BIT* (batch informed trees, runs for time_limit)";
  }
  return "";
}

std::vector<PlannerOptionSpec> OmplPlanner::options() const {
  return {{"time_limit", algorithm_ == Algorithm::kRrtConnect ? 1.0 : 0.25,
           "seconds of planning (optimising planners use all of it; RRT-Connect stops at the first solution)"},
          {"space", 0.0, "0: SE(2) (turns in place), 1: Dubins (forward only), 2: Reeds-Shepp (forward and reverse)"},
          {"turning_radius", 0.5, "metres, for the Dubins and Reeds-Shepp spaces"},
          {"start_yaw", 0.0, "radians, start heading (matters for Dubins and Reeds-Shepp)"},
          {"goal_yaw", 0.0, "radians, goal heading (matters for Dubins and Reeds-Shepp)"}};
}

CellPath OmplPlanner::Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal,
                           const PlannerOptions& options, const StopRequested& stop) const {
  static std::once_flag quiet;
  std::call_once(quiet, [] { ompl::msg::setLogLevel(ompl::msg::LOG_ERROR); });
  const double time_limit = options.at("time_limit"), radius = options.at("turning_radius");
  const int space_kind = static_cast<int>(options.at("space"));
  if (!(time_limit > 0.0 && time_limit <= 60.0)) {
    throw Error(ErrorCode::kInvalidArgument, "options: 'time_limit' must be in (0, 60] seconds");
  }
  if (options.at("space") != space_kind || space_kind < 0 || space_kind > 2) {
    throw Error(ErrorCode::kInvalidArgument, "options: 'space' must be 0 (SE2), 1 (Dubins) or 2 (Reeds-Shepp)");
  }
  if (!(radius > 0.0)) throw Error(ErrorCode::kInvalidArgument, "options: 'turning_radius' must be > 0");

  const OccupancyGrid& grid = costmap.grid();
  ob::StateSpacePtr space;
  if (space_kind == 1)
    space = std::make_shared<ob::DubinsStateSpace>(radius);
  else if (space_kind == 2)
    space = std::make_shared<ob::ReedsSheppStateSpace>(radius);
  else
    space = std::make_shared<ob::SE2StateSpace>();
  ob::RealVectorBounds bounds(2);
  bounds.setLow(0, grid.origin().x());
  bounds.setHigh(0, grid.origin().x() + grid.size_x());
  bounds.setLow(1, grid.origin().y());
  bounds.setHigh(1, grid.origin().y() + grid.size_y());
  space->as<ob::SE2StateSpace>()->setBounds(bounds);

  og::SimpleSetup setup(space);
  setup.setStateValidityChecker([&](const ob::State* s) {
    const auto* se2 = s->as<ob::SE2StateSpace::StateType>();
    const CellIndex c = grid.CellOf({se2->getX(), se2->getY()});
    return grid.Contains(c) && !costmap.IsLethal(c);
  });
  if (space_kind == 0) {
    setup.getSpaceInformation()->setMotionValidator(
        std::make_shared<SegmentMotionValidator>(setup.getSpaceInformation(), costmap));
  } else {
    // Curves are checked by sampling every quarter cell.
    setup.getSpaceInformation()->setStateValidityCheckingResolution(0.25 * grid.resolution() /
                                                                    space->getMaximumExtent());
  }
  const Point2 s = grid.CellCenter(start), g = grid.CellCenter(goal);
  ob::ScopedState<ob::SE2StateSpace> from(space), to(space);
  from->setXY(s.x(), s.y());
  from->setYaw(options.at("start_yaw"));
  to->setXY(g.x(), g.y());
  to->setYaw(options.at("goal_yaw"));
  setup.setStartAndGoalStates(from, to);

  const auto si = setup.getSpaceInformation();
  switch (algorithm_) {
    case Algorithm::kRrtConnect: setup.setPlanner(std::make_shared<og::RRTConnect>(si)); break;
    case Algorithm::kRrtStar: setup.setPlanner(std::make_shared<og::RRTstar>(si)); break;
    case Algorithm::kPrmStar: setup.setPlanner(std::make_shared<og::PRMstar>(si)); break;
    case Algorithm::kInformedRrtStar: setup.setPlanner(std::make_shared<og::InformedRRTstar>(si)); break;
    case Algorithm::kBitStar: setup.setPlanner(std::make_shared<og::BITstar>(si)); break;
  }
  setup.setOptimizationObjective(std::make_shared<ob::PathLengthOptimizationObjective>(si));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(time_limit);
  bool cancelled = false;
  const ob::PlannerTerminationCondition ptc([&] {
    if (stop && stop()) cancelled = true;
    return cancelled || std::chrono::steady_clock::now() > deadline;
  });
  const ob::PlannerStatus status = setup.solve(ptc);
  CellPath result;
  if (cancelled && !setup.haveExactSolutionPath()) {
    throw Error(ErrorCode::kDeadlineExceeded, "planning stopped: deadline exceeded or cancelled");
  }
  if (status != ob::PlannerStatus::EXACT_SOLUTION || !setup.haveExactSolutionPath()) return result;  // no path
  setup.simplifySolution(ob::PlannerTerminationCondition([&] { return stop && stop(); }));
  og::PathGeometric path = setup.getSolutionPath();
  // Straight SE(2) segments need no extra points; curves (Dubins, Reeds-Shepp) are sampled at
  // about one point per cell so followers and collision checks see their shape.
  if (space_kind != 0) path.interpolate(static_cast<unsigned>(std::ceil(path.length() / grid.resolution())) + 2);
  for (const ob::State* state : path.getStates()) {
    const auto* se2 = state->as<ob::SE2StateSpace::StateType>();
    result.points.emplace_back(se2->getX(), se2->getY());
    result.cells.push_back(grid.CellOf(result.points.back()));
  }
  result.keep_shape = space_kind != 0;
  ob::PlannerData data(si);
  setup.getPlannerData(data);
  result.expansions = static_cast<uint64_t>(data.numVertices());
  return result;
}

}  // namespace navd::planning
