#include "services/navigation/explorer.h"

#include <algorithm>
#include <cmath>

#include "services/common/error.h"

namespace navd::navigation {

Explorer::Explorer(MapStore& maps, mapping::MapBuilder& builder, NavigationExecutive& executive,
                   planning::PlanningEngine& planning, localization::LocalizerSelector& localizer, Clock& clock)
    : maps_(maps),
      builder_(builder),
      executive_(executive),
      planning_(planning),
      localizer_(localizer),
      clock_(clock) {}

Explorer::~Explorer() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

ExplorationProgress Explorer::Start(const ExplorerOptions& options) {
  std::lock_guard<std::mutex> run(run_mutex_);
  if (Progress().state == ExplorationState::kExploring)
    throw Error(ErrorCode::kFailedPrecondition, "exploring already: stop it first");
  if (!(options.max_time >= 0.0) || !std::isfinite(options.max_time))
    throw Error(ErrorCode::kInvalidArgument, "max_time must be a non-negative number of seconds");
  if (!(options.extra_inflation >= 0.0) || !std::isfinite(options.extra_inflation))
    throw Error(ErrorCode::kInvalidArgument, "extra_inflation must be a non-negative number of metres");
  if (!(options.squeeze >= 0.0) || !std::isfinite(options.squeeze))
    throw Error(ErrorCode::kInvalidArgument, "squeeze must be a non-negative number of metres");
  if (executive_.navigator().Status().active)
    throw Error(ErrorCode::kFailedPrecondition, "a navigation mission is active: cancel it before exploring");
  if (!options.planner.empty()) {
    bool known = false;
    for (const planning::PlannerInfo& p : planning_.Planners()) known = known || p.name == options.planner;
    if (!known) throw Error(ErrorCode::kInvalidArgument, "planner: unknown planner '" + options.planner + "'");
  }
  const localization::PoseEstimate estimate = localizer_.Estimate();
  if (!estimate.valid) throw Error(ErrorCode::kFailedPrecondition, "no pose estimate yet: exploration starts from it");
  if (thread_.joinable()) thread_.join();  // the last run's thread has ended

  // The SLAM run: an active one is explored on, a known-poses one cannot be (it needs a map).
  if (const auto session = builder_.session(); session && session->status().active) {
    if (session->status().mode != mapping::MappingMode::kSlam)
      throw Error(ErrorCode::kFailedPrecondition, "a known-poses mapping run is active: exploration needs SLAM");
  } else {
    mapping::MappingSessionOptions mapping = options.mapping;
    mapping.mode = mapping::MappingMode::kSlam;
    builder_.Start(mapping, estimate.pose);
  }
  localizer_.Select("slam");
  executive_.SetMapBuilding(true);
  options_ = options;
  inflation_before_ = planning_.inflation_radius();
  planning_.SetInflationRadius(ExploringInflation());

  started_ = clock_.Now();
  served_version_ = ~0ULL;
  visited_ = {estimate.pose.translation()};
  last_position_ = estimate.pose.translation();
  mission_ = 0;
  empty_decisions_ = 0;
  goal_record_ = ExplorationGoalRecord(options.exploration.exclusion_radius);
  for (const Point2& p : options.exploration.excluded) goal_record_.Reached(p);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    progress_ = ExplorationProgress{};
    progress_.state = ExplorationState::kExploring;
    progress_.method = options.method;
    progress_.message = "exploring";
    progress_.goal = estimate.pose;
  }
  stop_ = false;
  thread_ = std::thread([this] { Run(); });
  return Progress();
}

ExplorationProgress Explorer::Stop() {
  std::lock_guard<std::mutex> run(run_mutex_);
  if (Progress().state != ExplorationState::kExploring) throw Error(ErrorCode::kFailedPrecondition, "not exploring");
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (Progress().state == ExplorationState::kExploring) End(ExplorationState::kStopped, "stopped by request");
  return Progress();
}

ExplorationProgress Explorer::Progress() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return progress_;
}

void Explorer::Run() {
  double next = clock_.Now();
  while (!stop_) {
    // Bounded waits keep Stop() prompt when simulated time stalls.
    if (!clock_.SleepUntil(next, 0.05)) continue;
    const double now = clock_.Now();
    next = now + options_.period;
    try {
      if (!Decide(now)) return;
    } catch (const std::exception& e) {
      End(ExplorationState::kFailed, e.what());
      return;
    }
  }
}

bool Explorer::Decide(double now) {
  const auto session = builder_.session();
  if (!session || !session->status().active) {
    End(ExplorationState::kFailed, "the mapping run was stopped");
    return false;
  }
  if (options_.max_time > 0.0 && now - started_ > options_.max_time) {
    End(ExplorationState::kFailed, "the map was not complete after max_time");
    return false;
  }
  const mapping::MappingStatus mapping = session->status();
  if (mapping.scans < 2) return true;  // nothing seen yet
  const std::shared_ptr<const OccupancyGrid> map = session->Map();
  if (mapping.version != served_version_) {
    // Served as it grows: the executive plans each leg on the newest map.
    maps_.Set(*map, "exploring");
    served_version_ = mapping.version;
    planning_.CurrentCostmap();  // built here rather than in the control loop's blocked-path check
  }

  const localization::PoseEstimate estimate = localizer_.Estimate();
  const Point2 position = estimate.pose.translation();
  const double moved = Distance(last_position_, position);
  last_position_ = position;
  if (Distance(visited_.back(), position) > 0.5) visited_.push_back(position);
  size_t free_cells = 0;
  for (const int8_t v : map->cells()) free_cells += v >= 0 && v < options_.exploration.free_below;

  if (!TrackMission(position, now)) return false;

  options_.exploration.excluded = goal_record_.Excluded();
  std::optional<ExplorationStep> step =
      NextExplorationStep(*map, estimate.pose, options_.method, visited_, options_.exploration);
  bool squeeze = false;
  if (!step) {
    step = SqueezedStep(*map, estimate.pose);
    squeeze = step.has_value();
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    progress_.explored_area = static_cast<double>(free_cells) * map->resolution() * map->resolution();
    progress_.frontier_cells = step ? step->frontier_cells : 0;
    progress_.elapsed = now - started_;
    progress_.distance_travelled += moved;
  }
  if (!step) {
    // Three decisions in a row: a map redrawn after a loop closure can hide a frontier for a moment.
    if (++empty_decisions_ < options_.complete_after) return true;
    if (goal_record_.RetryGivenUp()) {
      empty_decisions_ = 0;
      return true;
    }
    End(ExplorationState::kComplete, "no reachable frontier is left");
    return false;
  }
  empty_decisions_ = 0;

  const bool refresh = mission_ == 0 || Distance(step->goal, frontier_goal_) > options_.goal_switch_distance ||
                       now - mission_started_ > options_.mission_refresh;
  if (!refresh) return true;
  SendGoal(*step, position, now, squeeze);
  return true;
}

bool Explorer::TrackMission(const Point2& position, double now) {
  const NavigationStatus nav = executive_.navigator().Status();
  if (mission_ != 0 && nav.goal_id != mission_) {
    End(ExplorationState::kStopped, "another navigation mission took the robot");
    return false;
  }
  if (mission_ != 0 && !nav.active) {
    const bool reached = nav.last_result && nav.last_result->outcome == Outcome::kSucceeded;
    if (!reached && nav.last_result && nav.last_result->outcome == Outcome::kCanceled) {
      End(ExplorationState::kStopped, "the exploration's mission was cancelled");
      return false;
    }
    // Reached, the robot faced the frontier: it is seen now, or cannot be seen from there.
    Exclude(frontier_goal_, !reached);
    mission_ = 0;
  }
  if (mission_ != 0) {
    const double remaining = Distance(position, progress_.goal.translation());
    if (remaining < best_remaining_ - 0.05) {
      best_remaining_ = remaining;
      last_progress_ = now;
    } else if (now - last_progress_ > options_.stuck_after) {
      executive_.Cancel(mission_);
      mission_ = 0;
      Exclude(frontier_goal_, true);
    }
  }
  return true;
}

void Explorer::SendGoal(const ExplorationStep& step, const Point2& position, double now, bool squeeze) {
  planning_.SetInflationRadius(squeeze ? SqueezeClearance() : ExploringInflation());
  const std::optional<Point2> target = ReachableEnd(step.path);
  if (!target) {
    Exclude(step.goal, true);
    return;
  }
  // Arrive facing the frontier, so the laser looks into the unknown.
  const Point2 look = Distance(step.goal, *target) > 0.05 ? Point2(step.goal - *target)
                      : step.path.size() > 1              ? Point2(step.path.back() - step.path[step.path.size() - 2])
                                                          : Point2(1.0, 0.0);
  NavigateRequest request;
  request.goal = Pose2(target->x(), target->y(), std::atan2(look.y(), look.x()));
  request.use_goal_heading = true;
  request.planner = options_.planner;
  request.preempt = true;
  try {
    const bool new_goal = mission_ == 0 || Distance(step.goal, frontier_goal_) > options_.goal_switch_distance;
    mission_ = executive_.Navigate(request);
    mission_started_ = now;
    frontier_goal_ = step.goal;
    if (new_goal) {
      best_remaining_ = Distance(position, *target);
      last_progress_ = now;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    progress_.goal = request.goal;
    progress_.goals += new_goal;
    progress_.message = squeeze ? "exploring: squeezing out through a way narrower than the clearance" : "exploring";
  } catch (const Error&) {
    // No path on the costmap (a narrow way the exploration's clearance allows), or the goal is
    // unusable: the next choice leaves it out.
    if (mission_ != 0) executive_.Cancel(mission_);
    mission_ = 0;
    Exclude(step.goal, true);
  }
}

std::optional<ExplorationStep> Explorer::SqueezedStep(const OccupancyGrid& map, const Pose2& robot) const {
  if (SqueezeClearance() >= options_.exploration.clearance) return std::nullopt;
  ExplorationOptions squeezed = options_.exploration;
  squeezed.squeeze_trail = visited_;
  squeezed.squeeze_trail.push_back(robot.translation());
  squeezed.squeeze_clearance = SqueezeClearance();
  return NextExplorationStep(map, robot, options_.method, visited_, squeezed);
}

double Explorer::ExploringInflation() const { return inflation_before_ + options_.extra_inflation; }

double Explorer::SqueezeClearance() const { return std::max(0.0, inflation_before_ - options_.squeeze); }

std::optional<Point2> Explorer::ReachableEnd(const std::vector<Point2>& path) const {
  const std::shared_ptr<const planning::Costmap> costmap = planning_.CurrentCostmap();
  const OccupancyGrid& grid = costmap->grid();
  for (auto it = path.rbegin(); it != path.rend(); ++it) {
    const CellIndex c = grid.CellOf(*it);
    if (grid.Contains(c) && !costmap->IsLethal(c)) return *it;
  }
  return std::nullopt;
}

void Explorer::Exclude(const Point2& frontier_goal, bool given_up) {
  if (given_up)
    goal_record_.GivenUp(frontier_goal);
  else
    goal_record_.Reached(frontier_goal);
  std::lock_guard<std::mutex> lock(mutex_);
  progress_.goals_given_up += given_up;
}

void Explorer::End(ExplorationState state, const std::string& message) {
  if (mission_ != 0) executive_.Cancel(mission_);
  mission_ = 0;
  if (const auto session = builder_.session(); session && session->status().active) {
    try {
      builder_.Stop();
    } catch (const Error&) {
      // Stopped by someone else meanwhile.
    }
  }
  if (const auto session = builder_.session()) maps_.Set(*session->Map(), "explored");
  executive_.SetMapBuilding(false);
  planning_.SetInflationRadius(inflation_before_);
  std::lock_guard<std::mutex> lock(mutex_);
  progress_.state = state;
  progress_.message = message;
  progress_.elapsed = clock_.Now() - started_;
}

}  // namespace navd::navigation
