#include "services/localization/beside_search.h"

#include <vector>

namespace navd::localization {

// Shared by the caller and the worker, so that the worker may outlive the BesideSearch.
struct BesideSearch::State {
  explicit State(std::unique_ptr<Localizer> l) : localizer(std::move(l)) {}
  std::unique_ptr<Localizer> localizer;  // the worker's alone while it runs (else the caller's)

  mutable std::mutex mutex;
  std::condition_variable wake;
  bool stop = false;
  std::deque<OdometryReading> odometry;  // not yet fed
  std::optional<ScanReading> scan;       // the newest not yet weighed
  std::optional<OccupancyGrid> map;      // a new map to hand over
  PoseEstimate estimate;
  uint64_t scans_used = 0;
};

namespace {
// Odometry arrives at 20-50 Hz; a worker held up this long (seconds) keeps the newest readings.
constexpr size_t kMaxQueuedOdometry = 4096;
}  // namespace

BesideSearch::BesideSearch(std::unique_ptr<Localizer> localizer, bool asynchronous)
    : state_(std::make_shared<State>(std::move(localizer))), asynchronous_(asynchronous) {
  state_->estimate = state_->localizer->Estimate();  // scattered over the map
  state_->estimate.valid = true;                     // a search runs
  if (asynchronous_) std::thread([state = state_] { Run(state); }).detach();
}

BesideSearch::~BesideSearch() {
  {
    std::lock_guard<std::mutex> lock(state_->mutex);
    state_->stop = true;
  }
  state_->wake.notify_all();
}

void BesideSearch::AddOdometry(const OdometryReading& reading) {
  if (!asynchronous_) {
    state_->localizer->AddOdometry(reading);
    return;
  }
  std::lock_guard<std::mutex> lock(state_->mutex);
  if (state_->odometry.size() >= kMaxQueuedOdometry) state_->odometry.pop_front();
  state_->odometry.push_back(reading);
}

void BesideSearch::AddScan(const ScanReading& scan) {
  if (!asynchronous_) {
    Weigh(*state_, scan);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(state_->mutex);
    state_->scan = scan;
  }
  state_->wake.notify_all();
}

void BesideSearch::SetMap(const OccupancyGrid& map) {
  if (!asynchronous_) {
    state_->localizer->SetMap(map);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(state_->mutex);
    state_->map = map;
  }
  state_->wake.notify_all();
}

PoseEstimate BesideSearch::Estimate() const {
  std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->estimate;
}

uint64_t BesideSearch::scans_used() const {
  std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->scans_used;
}

void BesideSearch::Weigh(State& s, const ScanReading& scan) {
  if (!s.localizer->AddScan(scan)) return;
  PoseEstimate e = s.localizer->Estimate();
  e.stamp = scan.stamp;
  std::lock_guard<std::mutex> lock(s.mutex);
  s.estimate = e;
  ++s.scans_used;
}

void BesideSearch::Run(const std::shared_ptr<State>& s) {
  std::unique_lock<std::mutex> lock(s->mutex);
  for (;;) {
    s->wake.wait(lock, [&] { return s->stop || s->scan || s->map; });
    if (s->stop) return;
    std::optional<OccupancyGrid> map = std::move(s->map);
    s->map.reset();
    std::optional<ScanReading> scan = std::move(s->scan);
    s->scan.reset();
    // The odometry up to the scan's stamp goes in first, so that the particles are carried to it.
    std::vector<OdometryReading> odometry;
    while (!s->odometry.empty() && (!scan || s->odometry.front().stamp <= scan->stamp)) {
      odometry.push_back(s->odometry.front());
      s->odometry.pop_front();
    }
    lock.unlock();
    if (map) s->localizer->SetMap(*map);
    for (const OdometryReading& r : odometry) s->localizer->AddOdometry(r);
    if (scan) Weigh(*s, *scan);
    lock.lock();
  }
}

}  // namespace navd::localization
