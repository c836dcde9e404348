#pragma once
// A map as a PNG image for people: 8-bit grey, north up, one pixel per cell, in map_server's
// trinary shades (occupied black, free white, unknown grey). Written atomically.
#include <string>

#include "services/common/occupancy_grid.h"

namespace navd {

// Throws navd::Error(kInvalidArgument) for an empty grid; std::runtime_error when the file cannot
// be written.
void SaveMapPng(const OccupancyGrid& grid, const std::string& path);

}  // namespace navd
