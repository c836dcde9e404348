#pragma once
// The occupancy grid that a log's own laser poses draw: in a corrected log, the map its publishers
// drew. It covers the traced end of every beam with a 1 m margin, at options.resolution unless
// that would take more cells than a grid holds (ResolutionToFit). Metres, the log's frame.
#include <cstddef>
#include <functional>

#include "services/common/carmen_log.h"
#include "services/common/occupancy_grid.h"
#include "services/mapping/occupancy_grid_mapper.h"

namespace navd::mapping {

// `progress` (optional) hears (scans mapped, scans) every 100 scans and at the end.
OccupancyGrid MapFromLogPoses(const CarmenLog& log, const MapperOptions& options,
                              const std::function<void(size_t, size_t)>& progress = {});

}  // namespace navd::mapping
