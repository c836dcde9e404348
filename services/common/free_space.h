#pragma once
// Which occupancy values count as free space. Maps loaded from map_server files hold 0 there; maps
// made in memory (the mapper's probabilities, a SLAM run's map) hold graded values, and a free cell
// seen by many clamped misses holds a few percent, not 0. Free is what map_server's default
// free_thresh (0.196) would have saved as free: known, and below 20 of 100.
#include <cstdint>

#include "services/common/occupancy_grid.h"

namespace navd {

constexpr int8_t kFreeBelow = 20;

inline bool IsFreeValue(int8_t value) { return value >= OccupancyGrid::kFree && value < kFreeBelow; }

}  // namespace navd
