#include "server/map_publisher.h"

#include <chrono>

namespace navd::server {

namespace {

// Nav2's costmap_2d as an OccupancyGrid: free 0, lethal 100, unknown -1, and the costs between
// (1..252) on 1..99.
std::vector<int8_t> PublishedCosts(const planning::Costmap& costmap) {
  const OccupancyGrid& grid = costmap.grid();
  std::vector<int8_t> out(grid.cells().size());
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const CellIndex c{x, y};
      const uint8_t cost = costmap.cost(c);
      int8_t v = 0;
      if (costmap.IsLethal(c)) {
        v = grid.at(c) == OccupancyGrid::kUnknown ? -1 : 100;
      } else if (cost > 0) {
        v = static_cast<int8_t>(1 + (98 * (cost - 1)) / (planning::Costmap::kMaxCost - 1));
      }
      out[grid.Flat(c)] = v;
    }
  }
  return out;
}

}  // namespace

MapPublisher::MapPublisher(DdsBridge& bridge, const MapStore& maps, const mapping::MapBuilder& builder,
                           const Clock& clock, SensedCostmap& costmaps, double building_period, double served_period,
                           double costmap_period)
    : bridge_(bridge),
      maps_(maps),
      builder_(builder),
      clock_(clock),
      costmaps_(costmaps),
      building_period_(building_period),
      served_period_(served_period),
      costmap_period_(costmap_period) {}

void MapPublisher::PublishCostmap(bool due) {
  std::shared_ptr<const planning::Costmap> costmap = costmaps_.Current();
  if (!costmap || (!due && costmap == costmap_)) return;
  costmap_ = costmap;
  bridge_.PublishCostmap(costmap->grid(), PublishedCosts(*costmap), clock_.Now());
}

MapPublisher::~MapPublisher() { Stop(); }

void MapPublisher::Start() {
  thread_ = std::thread([this] { Run(); });
}

void MapPublisher::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void MapPublisher::Run() {
  using Steady = std::chrono::steady_clock;
  Steady::time_point next_building = Steady::now(), next_served = Steady::now(), next_costmap = Steady::now(),
                     next_costmap_anyway = Steady::now();
  uint64_t served_version = 0;
  std::unique_lock<std::mutex> lock(mutex_);
  while (!wake_.wait_for(lock, std::chrono::milliseconds(200), [this] { return stop_; })) {
    lock.unlock();
    const Steady::time_point now = Steady::now();
    const auto session = builder_.session();
    if (session && session->status().active) {
      if (now >= next_building) {
        next_building =
            now + std::chrono::duration_cast<Steady::duration>(std::chrono::duration<double>(building_period_));
        bridge_.PublishMap(*session->Map(), clock_.Now());
      }
    } else if (const auto served = maps_.Get(); served && (served->version != served_version || now >= next_served)) {
      served_version = served->version;
      next_served = now + std::chrono::duration_cast<Steady::duration>(std::chrono::duration<double>(served_period_));
      bridge_.PublishMap(served->grid, clock_.Now());
    }
    if (now >= next_costmap) {
      next_costmap = now + std::chrono::duration_cast<Steady::duration>(std::chrono::duration<double>(costmap_period_));
      const bool due = now >= next_costmap_anyway;
      if (due)
        next_costmap_anyway =
            now + std::chrono::duration_cast<Steady::duration>(std::chrono::duration<double>(served_period_));
      PublishCostmap(due);
    }
    lock.lock();
  }
}

}  // namespace navd::server
