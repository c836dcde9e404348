#include "services/mapping/mapping_session.h"

#include <chrono>
#include <cmath>

#include "services/common/error.h"
#include "services/common/scan_reach.h"

namespace navd::mapping {
namespace {

constexpr size_t kKeptChanges = 256;

double WallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

MappingSession::MappingSession(const MappingSessionOptions& options, const Pose2& start) : o_(options) {
  if (!(o_.resolution >= 0.01 && o_.resolution <= 1.0))
    throw Error(ErrorCode::kInvalidArgument, "resolution must be in [0.01, 1] metres");
  if (!(o_.size > 0.0) || !std::isfinite(o_.size))
    throw Error(ErrorCode::kInvalidArgument, "size must be a positive number of metres");
  const double cells = std::ceil(o_.size / o_.resolution);
  if (cells * cells > static_cast<double>(OccupancyGrid::kMaxCells))
    throw Error(ErrorCode::kInvalidArgument, "size: " + std::to_string(static_cast<long long>(cells)) + " x " +
                                                 std::to_string(static_cast<long long>(cells)) +
                                                 " cells is more than " + std::to_string(OccupancyGrid::kMaxCells) +
                                                 " cells");
  if (!start.finite()) throw Error(ErrorCode::kInvalidArgument, "start pose is not finite");
  if (o_.max_waiting < 1) throw Error(ErrorCode::kInvalidArgument, "max_waiting must be at least 1");
  o_.mapper.resolution = o_.resolution;
  const Point2 half(o_.size / 2, o_.size / 2);
  mapper_ = std::make_unique<OccupancyGridMapper>(start.translation() - half, start.translation() + half, o_.mapper);
  geometry_ = mapper_->geometry();
  status_.active = true;
  status_.mode = o_.mode;
  status_.pose = start;
  if (!o_.synchronous) worker_ = std::thread([this] { Work(); });
}

MappingSession::~MappingSession() { Finish(); }

void MappingSession::Submit(const Pose2& odometry, const Pose2& localised, const RangeScan& scan) {
  if (o_.synchronous) {
    if (!status().active) return;
    try {
      Integrate({odometry, localised, scan});
    } catch (const std::exception&) {
      std::lock_guard<std::mutex> lock(mutex_);
      ++status_.dropped;
    }
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finishing_) return;
    if (static_cast<int>(waiting_.size()) >= o_.max_waiting) {
      waiting_.pop_front();
      ++status_.dropped;
    }
    waiting_.push_back(Item{odometry, localised, scan});
  }
  wake_.notify_one();
}

void MappingSession::Finish() {
  std::lock_guard<std::mutex> finishing(finish_mutex_);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finishing_) return;
    finishing_ = true;
    status_.active = false;
  }
  wake_.notify_one();
  if (worker_.joinable()) worker_.join();
  if (slam_) {
    // The run's end, as Cartographer's final optimisation: every node matched again against the
    // other passes near it (GraphSlam::Refine), and the map drawn from the poses that leaves. A
    // graph the refinement cannot solve keeps the poses it had (Finish runs in the destructor too).
    try {
      slam_->Refine();
    } catch (const std::exception&) {
    }
    Render();
    std::lock_guard<std::mutex> lock(mutex_);
    MarkChanged({{0, 0}, {geometry_.width() - 1, geometry_.height() - 1}});
  }
}

void MappingSession::Work() {
  while (true) {
    Item item;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return finishing_ || !waiting_.empty(); });
      if (waiting_.empty()) return;  // finishing, every scan handed over taken
      item = std::move(waiting_.front());
      waiting_.pop_front();
    }
    try {
      Integrate(item);
    } catch (const std::exception&) {
      // A reading the algorithms refuse (non-finite odometry, an unsolvable graph) costs that scan,
      // never the daemon.
      std::lock_guard<std::mutex> lock(mutex_);
      ++status_.dropped;
    }
  }
}

double MappingSession::RenderClock(double stamp) const { return o_.synchronous ? stamp : WallSeconds(); }

void MappingSession::Render() {
  auto fresh = std::make_unique<OccupancyGridMapper>(geometry_, o_.mapper);
  slam_->RenderInto(*fresh);
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  mapper_ = std::move(fresh);
  rendered_optimisations_ = slam_->optimisations();
}

void MappingSession::Integrate(const Item& item) {
  const OccupancyGrid& g = geometry_;
  auto footprint = [&](const Pose2& pose, const RangeScan& scan) {
    // The cells a scan can touch: its reach around the pose (none when that lies off the map).
    const double cut = ScanReachOf(o_.mapper, scan.ranges, scan.range_max);
    double reach = 0.0;
    for (float r : scan.ranges)
      if (IsReading(r)) reach = std::max(reach, TracedLength(o_.mapper, r, scan.range_max, cut));
    const CellIndex a = g.CellOf(pose.translation() - Point2(reach, reach));
    const CellIndex b = g.CellOf(pose.translation() + Point2(reach, reach));
    const MapRegion r{{std::max(0, a.x), std::max(0, a.y)},
                      {std::min(g.width() - 1, b.x), std::min(g.height() - 1, b.y)}};
    return r.min.x <= r.max.x && r.min.y <= r.max.y ? std::optional<MapRegion>(r) : std::nullopt;
  };
  Pose2 pose = item.localised;
  std::optional<MapRegion> changed;
  int nodes = 0, closures = 0;
  if (o_.mode == MappingMode::kSlam) {
    if (!slam_) {
      // The first node sits where the localiser puts the first scan: the robot may have moved
      // since the run started.
      GraphSlamOptions first = o_.slam;
      first.first_pose = item.localised;
      slam_ = std::make_unique<GraphSlam>(first);
    }
    const int nodes_before = slam_->nodes();
    pose = slam_->AddScan(item.odometry, item.scan);
    nodes = slam_->nodes();
    closures = slam_->loop_closures();
    const double now = RenderClock(item.scan.stamp);
    const bool rerender = slam_->optimisations() != rendered_optimisations_ && now - last_render_ >= o_.rerender_period;
    if (rerender) {
      // Loop closures moved the nodes: the map is drawn again from the optimised poses.
      Render();
      last_render_ = now;
      changed = MapRegion{{0, 0}, {g.width() - 1, g.height() - 1}};
    } else if (nodes != nodes_before) {
      std::lock_guard<std::mutex> lock(mapper_mutex_);
      const RangeScan& s = *slam_->last_node_scan();
      mapper_->AddScan(slam_->last_node_pose(), s.ranges, s.angle_min, s.angle_increment, s.range_max);
      changed = footprint(slam_->last_node_pose(), s);
    }
  } else {
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    mapper_->AddScan(pose, item.scan.ranges, item.scan.angle_min, item.scan.angle_increment, item.scan.range_max);
    changed = footprint(pose, item.scan);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  ++status_.scans;
  status_.pose = pose;
  status_.stamp = item.scan.stamp;
  status_.nodes = nodes;
  status_.loop_closures = closures;
  if (changed) MarkChanged(*changed);
}

void MappingSession::MarkChanged(const MapRegion& region) {
  ++status_.version;
  changes_.emplace_back(status_.version, region);
  if (changes_.size() > kKeptChanges) changes_.pop_front();
}

MappingStatus MappingSession::status() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return status_;
}

std::shared_ptr<const OccupancyGrid> MappingSession::Map() const {
  uint64_t version;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    version = status_.version;
    if (snapshot_ && snapshot_version_ == version) return snapshot_;
  }
  std::shared_ptr<const OccupancyGrid> grid;
  {
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    grid = std::make_shared<const OccupancyGrid>(mapper_->ToGrid());
  }
  std::lock_guard<std::mutex> lock(mutex_);
  snapshot_ = grid;
  snapshot_version_ = version;
  return grid;
}

std::optional<MapRegion> MappingSession::ChangedSince(uint64_t version, uint64_t* covers) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (covers) *covers = status_.version;
  if (version >= status_.version) return std::nullopt;
  const OccupancyGrid& g = geometry_;
  if (changes_.empty() || changes_.front().first > version + 1)
    return MapRegion{{0, 0}, {g.width() - 1, g.height() - 1}};  // older than the kept changes
  std::optional<MapRegion> out;
  for (const auto& [v, r] : changes_) {
    if (v <= version) continue;
    if (!out) {
      out = r;
    } else {
      out->min = {std::min(out->min.x, r.min.x), std::min(out->min.y, r.min.y)};
      out->max = {std::max(out->max.x, r.max.x), std::max(out->max.y, r.max.y)};
    }
  }
  return out;
}

}  // namespace navd::mapping
