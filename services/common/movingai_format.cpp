#include "services/common/movingai_format.h"

#include <cmath>
#include <sstream>

#include "services/common/error.h"
#include "services/common/text_file.h"

namespace navd {

OccupancyGrid ParseMovingAiMap(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  std::string key, type;
  long long height = -1, width = -1;
  int line_no = 0;
  auto fail = [&](const std::string& why) {
    throw Error(ErrorCode::kInvalidArgument, source + ":" + std::to_string(line_no) + ": " + why);
  };
  std::string line;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream f(line);
    f >> key;
    if (key == "type") {
      f >> type;
    } else if (key == "height") {
      if (!(f >> height)) fail("height is not a number");
    } else if (key == "width") {
      if (!(f >> width)) fail("width is not a number");
    } else if (key == "map") {
      break;
    } else {
      fail("unexpected header line '" + line + "' (expected type, height, width, map)");
    }
  }
  if (key != "map") fail("missing 'map' line: not a MovingAI map");
  if (type != "octile") fail("map type '" + type + "' is not octile");
  // Each side bounded before the product, which could overflow.
  if (height < 1 || width < 1 || height > OccupancyGrid::kMaxCells || width > OccupancyGrid::kMaxCells ||
      height * width > OccupancyGrid::kMaxCells) {
    fail("width and height must be positive, at most " + std::to_string(OccupancyGrid::kMaxCells) + " cells");
  }
  OccupancyGrid grid(static_cast<int>(width), static_cast<int>(height), 1.0, Point2::Zero(), OccupancyGrid::kFree);
  for (int row = 0; row < height; ++row) {
    ++line_no;
    if (!std::getline(in, line)) fail("map has " + std::to_string(row) + " rows, expected " + std::to_string(height));
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (static_cast<long long>(line.size()) != width) {
      fail("row has " + std::to_string(line.size()) + " cells, expected " + std::to_string(width));
    }
    for (int x = 0; x < width; ++x) {
      const char c = line[x];
      const bool passable = c == '.' || c == 'G' || c == 'S';
      grid.set({x, static_cast<int>(height) - 1 - row}, passable ? OccupancyGrid::kFree : OccupancyGrid::kOccupied);
    }
  }
  return grid;
}

OccupancyGrid LoadMovingAiMap(const std::string& path) {
  return ParseMovingAiMap(ReadTextFile(path, "map file"), path);
}

std::vector<MovingAiScenario> LoadMovingAiScenarios(const std::string& path) {
  return ParseMovingAiScenarios(ReadTextFile(path, "scenario file"), path);
}

std::vector<MovingAiScenario> ParseMovingAiScenarios(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  std::vector<MovingAiScenario> out;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line.rfind("version", 0) == 0) continue;
    std::istringstream f(line);
    MovingAiScenario s;
    int w = 0, h = 0;
    std::string optimal;
    if (!(f >> s.bucket >> s.map >> w >> h >> s.start_x >> s.start_row >> s.goal_x >> s.goal_row >> optimal)) {
      throw Error(ErrorCode::kInvalidArgument,
                  path + ":" + std::to_string(line_no) + ": expected 'bucket map width height sx sy gx gy optimal'");
    }
    char* end = nullptr;
    s.optimal_length = std::strtod(optimal.c_str(), &end);
    if (*end != '\0' || !std::isfinite(s.optimal_length)) {
      throw Error(ErrorCode::kInvalidArgument,
                  path + ":" + std::to_string(line_no) + ": optimal length '" + optimal + "' is not a number");
    }
    const size_t dot = optimal.find('.');
    s.decimals = dot == std::string::npos ? 0 : static_cast<int>(optimal.size() - dot - 1);
    out.push_back(s);
  }
  if (out.empty()) throw Error(ErrorCode::kInvalidArgument, path + ": no scenarios");
  return out;
}

Point2 MovingAiCellCenter(const OccupancyGrid& grid, int x, int row) {
  return grid.CellCenter({x, grid.height() - 1 - row});
}

}  // namespace navd
