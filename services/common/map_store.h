#pragma once
// The daemon's current map as an immutable snapshot. Readers take a shared_ptr and keep using it
// while a new map is swapped in; every swap bumps the version so caches (costmaps) can tell.
#include <memory>
#include <mutex>
#include <string>

#include "services/common/occupancy_grid.h"

namespace navd {

struct MapSnapshot {
  OccupancyGrid grid;
  std::string name;
  uint64_t version = 0;
};

class MapStore {
 public:
  std::shared_ptr<const MapSnapshot> Get() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return current_;
  }
  std::shared_ptr<const MapSnapshot> Set(OccupancyGrid grid, std::string name) {
    auto next = std::make_shared<MapSnapshot>();
    next->grid = std::move(grid);
    next->name = std::move(name);
    std::lock_guard<std::mutex> lock(mutex_);
    next->version = current_ ? current_->version + 1 : 1;
    current_ = next;
    return next;
  }

 private:
  mutable std::mutex mutex_;
  std::shared_ptr<const MapSnapshot> current_;
};

}  // namespace navd
