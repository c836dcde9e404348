#pragma once
// The MovingAI grid benchmark formats (Sturtevant, "Benchmarks for Grid-Based Pathfinding"): `.map`
// grids ("type octile", height, width, then rows of terrain characters, top row first) and `.scen`
// scenario lists with optimal octile lengths. Cells are 1 m; the map's lower-left corner is the
// map-frame origin, so MovingAI cell (x, row) has its centre at (x + 0.5, height - row - 0.5).
#include <string>
#include <vector>

#include "services/common/occupancy_grid.h"

namespace navd {

// Passable terrain is '.', 'G' and 'S'; everything else ('@', 'O', 'T', 'W') is an obstacle.
OccupancyGrid ParseMovingAiMap(const std::string& text, const std::string& source);
OccupancyGrid LoadMovingAiMap(const std::string& path);

struct MovingAiScenario {
  int bucket = 0;
  std::string map;
  int start_x = 0, start_row = 0;  // MovingAI coordinates: column, row from the top
  int goal_x = 0, goal_row = 0;
  double optimal_length = 0.0;
  int decimals = 0;  // digits after the point in the file's optimal length
};

// `source` names the file in error messages.
std::vector<MovingAiScenario> ParseMovingAiScenarios(const std::string& text, const std::string& source);
std::vector<MovingAiScenario> LoadMovingAiScenarios(const std::string& path);

// Map-frame centre of MovingAI cell (x, row) in `grid`, which was loaded from a `.map`.
Point2 MovingAiCellCenter(const OccupancyGrid& grid, int x, int row);

}  // namespace navd
