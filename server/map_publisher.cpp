#include "server/map_publisher.h"

#include <chrono>

namespace navd::server {

MapPublisher::MapPublisher(DdsBridge& bridge, const MapStore& maps, const mapping::MapBuilder& builder,
                           const Clock& clock, double building_period, double served_period)
    : bridge_(bridge),
      maps_(maps),
      builder_(builder),
      clock_(clock),
      building_period_(building_period),
      served_period_(served_period) {}

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
  Steady::time_point next_building = Steady::now(), next_served = Steady::now();
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
    lock.lock();
  }
}

}  // namespace navd::server
