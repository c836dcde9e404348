#pragma once
// Mazes of wide corridors by the rules of MovingAI's maze family (maze512-32: a 512 x 512 map of
// 32-cell corridors), for planning benchmarks and tests: the map is divided into square rooms of
// `corridor` cells by walls one cell thick; a growing-tree search (the newest room nine times in ten,
// a random one otherwise) knocks down the wall between a room and an unvisited neighbour until
// every room is reached, so the maze is perfect (one route between any two rooms). Wall
// crossings stay solid. Cells are 1 m, as in MovingAI maps.
#include <cstdint>
#include <random>
#include <vector>

#include "services/common/occupancy_grid.h"

namespace navd::testing {

inline OccupancyGrid CorridorMaze(int size, int corridor, uint32_t seed) {
  OccupancyGrid g(size, size, 1.0, Point2::Zero(), OccupancyGrid::kFree);
  const int pitch = corridor + 1;
  for (int i = 0; i < size; i += pitch)
    for (int j = 0; j < size; ++j) {
      g.set({i, j}, OccupancyGrid::kOccupied);
      g.set({j, i}, OccupancyGrid::kOccupied);
    }
  const int rooms = (size - 2) / pitch + 1;  // the last room may be cut short by the map's edge
  std::vector<uint8_t> visited(static_cast<size_t>(rooms) * rooms, 0);
  std::mt19937 rng(seed);
  std::vector<std::pair<int, int>> open{{rooms / 2, rooms / 2}};
  visited[static_cast<size_t>(rooms / 2) * rooms + rooms / 2] = 1;
  while (!open.empty()) {
    const size_t k = rng() % 10 != 0 ? open.size() - 1 : rng() % open.size();
    const auto [rx, ry] = open[k];
    std::vector<std::pair<int, int>> unvisited;
    for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
      const int nx = rx + dx, ny = ry + dy;
      if (nx >= 0 && ny >= 0 && nx < rooms && ny < rooms && !visited[static_cast<size_t>(ny) * rooms + nx])
        unvisited.emplace_back(nx, ny);
    }
    if (unvisited.empty()) {
      open.erase(open.begin() + static_cast<long>(k));
      continue;
    }
    const auto [nx, ny] = unvisited[rng() % unvisited.size()];
    visited[static_cast<size_t>(ny) * rooms + nx] = 1;
    // The wall line between the two rooms, without its crossings.
    if (nx != rx) {
      const int x = std::max(rx, nx) * pitch;
      for (int y = ry * pitch + 1; y < std::min(size, (ry + 1) * pitch); ++y) g.set({x, y}, OccupancyGrid::kFree);
    } else {
      const int y = std::max(ry, ny) * pitch;
      for (int x = rx * pitch + 1; x < std::min(size, (rx + 1) * pitch); ++x) g.set({x, y}, OccupancyGrid::kFree);
    }
    open.emplace_back(nx, ny);
  }
  return g;
}

}  // namespace navd::testing
