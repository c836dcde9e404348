#pragma once
// Reads maps in the ROS map_server format: a YAML file (image, resolution, origin, negate,
// occupied_thresh, free_thresh, mode) naming a PGM image. Throws navd::Error naming the bad field.
#include <cstdint>
#include <string>
#include <vector>

#include "services/common/occupancy_grid.h"

namespace navd {

// path: the map_server YAML. Relative image paths resolve against the YAML's folder.
OccupancyGrid LoadMapServerMap(const std::string& yaml_path);

// Writes `grid` as map_server YAML + PGM (trinary: occupied >= 65 black, free < 20 white (254),
// else unknown grey (205), as ROS's map_saver does). The PGM goes beside the YAML, named after it;
// both files are written atomically.
void SaveMapServerMap(const OccupancyGrid& grid, const std::string& yaml_path);

// The map as grey pixels, top row (largest y) first: occupied 0, free 254, unknown 205 (what
// map_server's trinary mode reads back). Shared by the PGM and PNG writers.
std::vector<uint8_t> MapImage(const OccupancyGrid& grid);

// Decodes an 8-bit PGM (P5 binary or P2 ASCII) into map cells as map_server's trinary/scale/raw
// modes do. `source` names the file in error messages.
struct MapServerParams {
  double resolution = 0.05;
  Point2 origin = Point2::Zero();
  bool negate = false;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  std::string mode = "trinary";
};
// The YAML's fields, checked; `image` gets the image path as written. `source` names the file.
MapServerParams ParseMapServerYaml(const std::string& text, const std::string& source, std::string* image);
OccupancyGrid DecodeMapServerImage(const std::string& pgm_bytes, const MapServerParams& params,
                                   const std::string& source);

}  // namespace navd
