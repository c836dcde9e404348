#include "server/sensed_costmap.h"

namespace navd::server {

std::shared_ptr<const planning::Costmap> SensedCostmap::Current() {
  std::shared_ptr<const planning::Costmap> base = planning_.CurrentCostmap();
  const uint64_t layer_version = layer_ ? layer_->version() : 0;
  std::lock_guard<std::mutex> lock(mutex_);
  if (base == base_ && layer_version == layer_version_ && current_) return current_;
  base_ = base;
  layer_version_ = layer_version;
  current_ = base;
  if (!base || !layer_) return current_;
  const auto cells = layer_->Obstacles();
  if (cells->empty()) return current_;
  OccupancyGrid grid = base->grid();
  for (const Point2& p : *cells)
    if (grid.ContainsPoint(p)) grid.set(grid.CellOf(p), OccupancyGrid::kOccupied);
  current_ = std::make_shared<const planning::Costmap>(std::make_shared<const OccupancyGrid>(std::move(grid)),
                                                       base->options());
  return current_;
}

}  // namespace navd::server
