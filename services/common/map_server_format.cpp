#include "services/common/map_server_format.h"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "services/common/error.h"
#include "services/common/text_file.h"
#include "services/common/yaml_document.h"

namespace navd {
namespace {

// Reads the next whitespace-separated header token of a PGM, skipping '#' comments.
bool NextToken(const std::string& s, size_t& pos, std::string& token) {
  token.clear();
  while (pos < s.size()) {
    if (s[pos] == '#') {
      while (pos < s.size() && s[pos] != '\n') ++pos;
    } else if (std::isspace(static_cast<unsigned char>(s[pos]))) {
      ++pos;
    } else {
      break;
    }
  }
  while (pos < s.size() && !std::isspace(static_cast<unsigned char>(s[pos]))) token += s[pos++];
  return !token.empty();
}

// A PGM header or raster integer of at least `min`.
int ParseInt(const std::string& token, const std::string& what, const std::string& source, int min) {
  try {
    size_t used = 0;
    const int v = std::stoi(token, &used);
    if (used == token.size() && v >= min) return v;
  } catch (const std::exception&) {
  }
  throw Error(ErrorCode::kInvalidArgument,
              source + ": PGM " + what + " '" + token + "' is not an integer >= " + std::to_string(min));
}

}  // namespace

OccupancyGrid DecodeMapServerImage(const std::string& bytes, const MapServerParams& p, const std::string& source) {
  size_t pos = 0;
  std::string magic, tok;
  if (!NextToken(bytes, pos, magic) || (magic != "P5" && magic != "P2")) {
    throw Error(ErrorCode::kInvalidArgument, source + ": not a PGM image (expected P5 or P2 header)");
  }
  if (!NextToken(bytes, pos, tok)) throw Error(ErrorCode::kInvalidArgument, source + ": PGM header truncated (width)");
  const int width = ParseInt(tok, "width", source, 1);
  if (!NextToken(bytes, pos, tok)) throw Error(ErrorCode::kInvalidArgument, source + ": PGM header truncated (height)");
  const int height = ParseInt(tok, "height", source, 1);
  if (!NextToken(bytes, pos, tok)) throw Error(ErrorCode::kInvalidArgument, source + ": PGM header truncated (maxval)");
  const int maxval = ParseInt(tok, "maxval", source, 1);
  if (maxval > 255) throw Error(ErrorCode::kInvalidArgument, source + ": 16-bit PGM images are not supported");
  if (static_cast<long long>(width) * height > OccupancyGrid::kMaxCells) {
    throw Error(ErrorCode::kInvalidArgument, source + ": PGM image of " + std::to_string(width) + "x" +
                                                 std::to_string(height) + " exceeds navd's limit of " +
                                                 std::to_string(OccupancyGrid::kMaxCells) + " cells");
  }

  std::vector<int> pixels(static_cast<size_t>(width) * height);
  if (magic == "P5") {
    ++pos;  // exactly one whitespace byte separates the header from the raster
    if (bytes.size() < pos + pixels.size()) {
      throw Error(ErrorCode::kInvalidArgument,
                  source + ": PGM raster truncated (expected " + std::to_string(pixels.size()) + " bytes)");
    }
    for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<unsigned char>(bytes[pos + i]);
  } else {
    for (auto& px : pixels) {
      if (!NextToken(bytes, pos, tok)) throw Error(ErrorCode::kInvalidArgument, source + ": PGM raster truncated");
      px = ParseInt(tok, "pixel", source, 0);
    }
  }
  for (size_t i = 0; i < pixels.size(); ++i) {
    if (pixels[i] > maxval) {
      throw Error(ErrorCode::kInvalidArgument,
                  source + ": PGM pixel " + std::to_string(i) + " exceeds maxval " + std::to_string(maxval));
    }
  }

  OccupancyGrid grid(width, height, p.resolution, p.origin, OccupancyGrid::kUnknown);
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      const double value = static_cast<double>(pixels[static_cast<size_t>(row) * width + col]) / maxval;
      // map_server: occupancy is darkness unless negated.
      const double occ = p.negate ? value : 1.0 - value;
      int8_t cell;
      if (p.mode == "raw") {
        cell = static_cast<int8_t>(std::lround(value * maxval > 100 ? -1 : value * maxval));
      } else if (occ > p.occupied_thresh) {
        cell = OccupancyGrid::kOccupied;
      } else if (occ < p.free_thresh) {
        cell = OccupancyGrid::kFree;
      } else if (p.mode == "scale") {
        cell = static_cast<int8_t>(std::lround(99.0 * (occ - p.free_thresh) / (p.occupied_thresh - p.free_thresh)));
      } else {
        cell = OccupancyGrid::kUnknown;
      }
      grid.set({col, height - 1 - row}, cell);  // images are stored top row first
    }
  }
  return grid;
}

std::vector<uint8_t> MapImage(const OccupancyGrid& grid) {
  std::vector<uint8_t> image(grid.cells().size());
  for (int y = 0; y < grid.height(); ++y)
    for (int x = 0; x < grid.width(); ++x) {
      const int8_t v = grid.at({x, y});
      uint8_t px = 205;
      if (v >= OccupancyGrid::kOccupiedThreshold)
        px = 0;
      else if (OccupancyGrid::IsFreeValue(v))
        px = 254;
      image[static_cast<size_t>(grid.height() - 1 - y) * grid.width() + x] = px;
    }
  return image;
}

void SaveMapServerMap(const OccupancyGrid& grid, const std::string& yaml_path) {
  const std::filesystem::path yaml(yaml_path);
  const std::filesystem::path pgm = std::filesystem::path(yaml).replace_extension(".pgm");
  std::string image =
      "P5\n# navd map\n" + std::to_string(grid.width()) + " " + std::to_string(grid.height()) + "\n255\n";
  const std::vector<uint8_t> pixels = MapImage(grid);
  image.append(reinterpret_cast<const char*>(pixels.data()), pixels.size());
  std::ostringstream meta;
  meta.precision(10);
  meta << "image: " << pgm.filename().string() << "\nresolution: " << grid.resolution() << "\norigin: ["
       << grid.origin().x() << ", " << grid.origin().y() << ", 0.0]\nnegate: 0\noccupied_thresh: 0.65\n"
       << "free_thresh: 0.196\nmode: trinary\n";
  WriteFileAtomically(pgm.string(), image);
  WriteFileAtomically(yaml.string(), meta.str());
}

OccupancyGrid LoadMapServerMap(const std::string& yaml_path) {
  std::string image;
  const MapServerParams p = ParseMapServerYaml(ReadTextFile(yaml_path, "map file"), yaml_path, &image);
  std::filesystem::path image_path(image);
  if (image_path.is_relative()) image_path = std::filesystem::path(yaml_path).parent_path() / image_path;
  const std::string bytes = ReadTextFile(image_path.string(), "map image");
  return DecodeMapServerImage(bytes, p, image_path.string());
}

MapServerParams ParseMapServerYaml(const std::string& text, const std::string& yaml_path, std::string* image_out) {
  const YAML::Node doc = ParseYamlMapping(text, yaml_path);
  auto require = [&](const char* key) {
    if (!doc[key]) throw Error(ErrorCode::kInvalidArgument, yaml_path + ": missing field '" + key + "'");
    return doc[key];
  };
  MapServerParams p;
  std::string image;
  try {
    image = require("image").as<std::string>();
    p.resolution = require("resolution").as<double>();
    const auto origin = require("origin");
    if (!origin.IsSequence() || origin.size() < 2) {
      throw Error(ErrorCode::kInvalidArgument, yaml_path + ": field 'origin' must be [x, y, yaw]");
    }
    // The origin's yaw is ignored, as by Nav2's costmaps; maps are axis-aligned.
    p.origin = {origin[0].as<double>(), origin[1].as<double>()};
    if (doc["negate"]) p.negate = doc["negate"].as<int>() != 0;
    if (doc["occupied_thresh"]) p.occupied_thresh = doc["occupied_thresh"].as<double>();
    if (doc["free_thresh"]) p.free_thresh = doc["free_thresh"].as<double>();
    if (doc["mode"]) p.mode = doc["mode"].as<std::string>();
  } catch (const YAML::Exception& e) {
    throw Error(ErrorCode::kInvalidArgument, yaml_path + ": bad value: " + e.what());
  }
  if (!(p.resolution > 0.0) || !std::isfinite(p.resolution)) {
    throw Error(ErrorCode::kInvalidArgument, yaml_path + ": field 'resolution' must be a positive number");
  }
  if (!p.origin.allFinite()) throw Error(ErrorCode::kInvalidArgument, yaml_path + ": field 'origin' must be finite");
  if (!(p.occupied_thresh >= 0.0 && p.occupied_thresh <= 1.0)) {
    throw Error(ErrorCode::kInvalidArgument, yaml_path + ": field 'occupied_thresh' must be within [0, 1]");
  }
  if (!(p.free_thresh >= 0.0 && p.free_thresh < p.occupied_thresh)) {
    throw Error(ErrorCode::kInvalidArgument, yaml_path + ": field 'free_thresh' must be within [0, occupied_thresh)");
  }
  if (p.mode != "trinary" && p.mode != "scale" && p.mode != "raw") {
    throw Error(ErrorCode::kInvalidArgument, yaml_path + ": field 'mode' must be trinary, scale or raw");
  }
  *image_out = image;
  return p;
}

}  // namespace navd
