#include "tools/navd_replay/log_map.h"

#include <cstdio>

#include "services/common/map_server_format.h"
#include "services/common/png_format.h"
#include "services/common/ray_caster.h"
#include "services/common/text_file.h"
#include "services/mapping/known_pose_map.h"
#include "services/mapping/occupancy_grid_mapper.h"

namespace navd::replay {

void NoteCoarserMap(const OccupancyGrid& grid, double resolution) {
  if (grid.resolution() > resolution + 1e-9)
    std::fprintf(stderr,
                 "navd-replay: the map spans %.0f x %.0f m: drawn at %.3f m, not %.3f, to stay within %lld cells\n",
                 grid.width() * grid.resolution(), grid.height() * grid.resolution(), grid.resolution(), resolution,
                 OccupancyGrid::kMaxCells);
}

OccupancyGrid MapFromLog(const CarmenLog& log, double resolution) {
  mapping::MapperOptions o;
  o.resolution = resolution;
  OccupancyGrid grid = mapping::MapFromLogPoses(
      log, o, [](size_t done, size_t total) { std::fprintf(stderr, "\r  mapped %zu/%zu scans", done, total); });
  std::fprintf(stderr, "\n");
  NoteCoarserMap(grid, resolution);
  return grid;
}

int BuildMap(const CarmenLog& log, const std::string& out, double resolution, const std::string& png) {
  const OccupancyGrid grid = MapFromLog(log, resolution);
  SaveMapServerMap(grid, out);
  if (!png.empty()) SaveMapPng(grid, png);
  std::printf("map: %dx%d cells at %.3f m, origin (%.2f, %.2f), from %zu scans -> %s\n", grid.width(), grid.height(),
              grid.resolution(), grid.origin().x(), grid.origin().y(), log.scans.size(), out.c_str());
  return 0;
}

int Render(const CarmenLog& log, const std::string& out, double resolution, const mapping::LogRenderOptions& options) {
  const OccupancyGrid map = MapFromLog(log, resolution);
  // People walk by the clock: a log whose stamps say too little is paced from its motion first.
  // Without people the stamps are the log's own.
  CarmenLog timed = log;
  if (options.people.count > 0) PaceScansWhenStampsAreCoarse(timed);
  const CarmenLog rendered = mapping::RenderLog(timed, RayCaster(map), options);
  WriteFileAtomically(out, FormatFlaserLog(rendered, "navd-replay"));
  std::printf(
      "render: %zu scans from the log's %zu, in its %dx%d-cell map at %.3f m, range noise %.3f m, %d people -> %s\n",
      rendered.scans.size(), log.scans.size(), map.width(), map.height(), map.resolution(), options.range_noise,
      options.people.count, out.c_str());
  return 0;
}

}  // namespace navd::replay
