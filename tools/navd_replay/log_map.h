#pragma once
// navd-replay --mode map and --mode render: the occupancy grid a log's (corrected) laser poses draw
// (services/mapping/known_pose_map.h), and the log's scans cast again in it
// (services/mapping/log_renderer.h).
#include <string>

#include "services/common/carmen_log.h"
#include "services/common/occupancy_grid.h"
#include "services/mapping/log_renderer.h"

namespace navd::replay {

// Says so on stderr when a map spread too wide for a grid at `resolution` (m per cell) was drawn
// coarser (ResolutionToFit).
void NoteCoarserMap(const OccupancyGrid& grid, double resolution);

// The map the log's poses draw at `resolution` m per cell (coarser when it would not fit), with
// progress on stderr.
OccupancyGrid MapFromLog(const CarmenLog& log, double resolution);

// --mode map: that map saved as map_server YAML + PGM at `out`, and as a PNG at `png` unless it is
// empty, each atomically. Prints one line; returns the exit code.
int BuildMap(const CarmenLog& log, const std::string& out, double resolution, const std::string& png);

// --mode render: the log's scans cast again in that map, written to `out` as a FLASER log.
int Render(const CarmenLog& log, const std::string& out, double resolution, const mapping::LogRenderOptions& options);

}  // namespace navd::replay
