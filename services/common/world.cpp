#include "services/common/world.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "services/common/error.h"
#include "services/common/distance_field.h"
#include "services/common/map_server_format.h"
#include "services/common/movingai_format.h"
#include "services/common/text_file.h"
#include "services/common/polygon.h"
#include "services/common/world_fields.h"
#include "services/common/yaml_document.h"
#include "services/common/yaml_fields.h"

extern "C" const char navd_default_world_yaml[];

namespace navd {
namespace {

constexpr const char* kRobotKeys[] = {"start",
                                      "drive",
                                      "radius",
                                      "height",
                                      "wheel_base",
                                      "wheel_radius",
                                      "max_wheel_speed",
                                      "max_wheel_accel",
                                      "encoder_ticks_per_rev",
                                      "actuator_noise",
                                      "encoder_noise",
                                      "omni_wheel_distance",
                                      "omni_wheel_angles_deg",
                                      "max_speed",
                                      "max_angular_speed",
                                      "max_accel",
                                      "max_angular_accel"};

OccupancyGrid InlineMap(const YamlFields& f, const YAML::Node& m, const std::string& base_dir) {
  f.CheckKeys(m, "map", {"resolution", "size", "origin", "boxes", "polygons", "boundary"});
  const double res = m["resolution"] ? f.Positive(m["resolution"], "map.resolution") : 0.05;
  if (!m["size"]) f.Fail("map.size", "is missing (expected [width_m, height_m])", m);
  const auto size = f.Numbers(m["size"], "map.size", 2, 2);
  const long long cells_x = std::llround(size[0] / res), cells_y = std::llround(size[1] / res);
  // Each side checked before the product, which would overflow for sides of 2^32 cells and more.
  if (cells_x < 1 || cells_y < 1 || cells_x > OccupancyGrid::kMaxCells || cells_y > OccupancyGrid::kMaxCells ||
      cells_x * cells_y > OccupancyGrid::kMaxCells) {
    f.Fail("map.size",
           "must span at least one cell and at most " + std::to_string(OccupancyGrid::kMaxCells) +
               " cells at this resolution",
           m["size"]);
  }
  Point2 origin = Point2::Zero();
  if (m["origin"]) {
    const auto o = f.Numbers(m["origin"], "map.origin", 2, 3);
    origin = {o[0], o[1]};
  }
  OccupancyGrid grid(static_cast<int>(cells_x), static_cast<int>(cells_y), res, origin, OccupancyGrid::kFree);
  auto polygon = [&](const YAML::Node& n, const std::string& field) {
    Polygon p = f.Points(n, field, 3);
    if (auto defect = PolygonDefect(p)) f.Fail(field, "is not a simple closed curve: it " + *defect, n);
    return p;
  };
  // The boundary first: it is the outline of the free space; boxes and polygons are solid inside it.
  if (m["boundary"]) FillOutsidePolygon(grid, polygon(m["boundary"], "map.boundary"));
  if (m["boxes"]) {
    f.ExpectSequence(m["boxes"], "map.boxes", "[x_min, y_min, x_max, y_max]");
    for (size_t i = 0; i < m["boxes"].size(); ++i) {
      const Box b = ReadBox(f, m["boxes"][i], "map.boxes[" + std::to_string(i) + "]");
      grid.FillBox(b.min, b.max);
    }
  }
  if (m["polygons"]) {
    f.ExpectSequence(m["polygons"], "map.polygons", "closed curves (lists of [x, y] vertices)");
    for (size_t i = 0; i < m["polygons"].size(); ++i) {
      FillPolygon(grid, polygon(m["polygons"][i], "map.polygons[" + std::to_string(i) + "]"));
    }
  }
  (void)base_dir;
  return grid;
}

World Parse(const YamlFields& f, const std::string& text, const std::string& base_dir) {
  const YAML::Node doc = ParseYamlMapping(text, f.source());
  f.CheckKeys(doc, "", {"name", "map", "robot", "laser", "camera", "goals", "regions", "speed_zones"});
  World w;
  w.source = f.source();
  w.name = doc["name"] ? f.String(doc["name"], "name") : std::filesystem::path(f.source()).stem().string();
  const YAML::Node map = doc["map"];
  if (!map) f.Fail("map", "is missing (a map_server YAML or MovingAI .map path, or an inline map)");
  if (map.IsScalar()) {
    std::filesystem::path p(map.as<std::string>());
    if (p.is_relative()) p = std::filesystem::path(base_dir) / p;
    // A world file's map serves another world too (the same floor for a different robot); a
    // chain of worlds that leads back to itself is refused at the fifth file.
    thread_local int worlds_open = 0;
    if (worlds_open >= 4) f.Fail("map", "leads through more than 4 world files (a world that names itself?)", map);
    struct Open {
      Open() { ++worlds_open; }
      ~Open() { --worlds_open; }
      Open(const Open&) = delete;
      Open& operator=(const Open&) = delete;
    } open;
    w.map = LoadAnyMapFile(p.string());
  } else if (map.IsMap()) {
    w.map = InlineMap(f, map, base_dir);
  } else {
    f.Fail("map", "must be a file path or a mapping", map);
  }
  if (const YAML::Node r = doc["robot"]) {
    f.ExpectMap(r, "robot");
    if (r["start"]) w.start = f.PoseOf(r["start"], "robot.start");
    ReadRobotDescription(f, r, "robot.", w.robot);
  }
  if (const YAML::Node l = doc["laser"]) ReadLaserDescription(f, l, "laser.", w.laser);
  if (const YAML::Node c = doc["camera"]) {
    w.camera.emplace();
    ReadDepthCameraDescription(f, c, "camera.", *w.camera);
  }
  if (const YAML::Node g = doc["goals"]) {
    f.ExpectSequence(g, "goals", "[x, y] or [x, y, theta]");
    for (size_t i = 0; i < g.size(); ++i) w.goals.push_back(f.PoseOf(g[i], "goals[" + std::to_string(i) + "]"));
  }
  if (const YAML::Node regions = doc["regions"]) {
    f.ExpectMap(regions, "regions");
    for (const auto& kv : regions) {
      const std::string name = f.String(kv.first, "regions");
      w.regions[name] = ReadBox(f, kv.second, "regions." + name);
    }
  }
  if (const YAML::Node zones = doc["speed_zones"]) {
    f.ExpectSequence(zones, "speed_zones",
                     "{name, box: [x_min, y_min, x_max, y_max] or polygon: [[x, y], ...], max_speed}");
    for (size_t i = 0; i < zones.size(); ++i) {
      const std::string field = "speed_zones[" + std::to_string(i) + "]";
      const YAML::Node z = zones[i];
      f.ExpectMap(z, field);
      f.CheckKeys(z, field, {"name", "box", "polygon", "max_speed"});
      SpeedZone zone;
      zone.name = z["name"] ? f.String(z["name"], field + ".name") : "zone " + std::to_string(i);
      if (z["box"].IsDefined() == z["polygon"].IsDefined()) f.Fail(field, "needs exactly one of box and polygon", z);
      const std::string shape = z["box"] ? "box" : "polygon";
      if (z["box"]) {
        const Box b = ReadBox(f, z["box"], field + ".box");
        zone.area = {b.min, {b.max.x(), b.min.y()}, b.max, {b.min.x(), b.max.y()}};
      } else {
        zone.area = f.Points(z["polygon"], field + ".polygon", 3);
      }
      if (auto defect = PolygonDefect(zone.area)) {
        f.Fail(field + "." + shape, "is not a simple closed curve: it " + *defect, z[shape]);
      }
      if (!z["max_speed"]) f.Fail(field + ".max_speed", "is missing (m/s)", z);
      zone.max_speed = f.Positive(z["max_speed"], field + ".max_speed");
      for (const SpeedZone& other : w.speed_zones)
        if (other.name == zone.name) f.Fail(field + ".name", "'" + zone.name + "' names two zones", z["name"]);
      w.speed_zones.push_back(std::move(zone));
    }
  }
  if (!w.map.ContainsPoint(w.start.translation())) f.Fail("robot.start", "lies outside the map", doc["robot"]);
  if (w.map.DiscHitsObstacle(w.start.translation(), w.robot.radius)) {
    f.Fail(
        "robot.start",
        "puts the robot (radius " + std::to_string(w.robot.radius).substr(0, 4) + " m) inside or against an obstacle",
        doc["robot"]);
  }
  return w;
}

}  // namespace

const char* DriveTypeName(DriveType type) {
  switch (type) {
    case DriveType::kDiffDrive: return "diff_drive";
    case DriveType::kOmni: return "omni";
    case DriveType::kUnicycle: return "unicycle";
  }
  return "?";
}

void ReadRobotDescription(const YamlFields& f, const YAML::Node& r, const std::string& prefix, RobotDescription& d,
                          const std::vector<std::string>& extra_keys) {
  f.ExpectMap(r, prefix.substr(0, prefix.size() - 1));
  for (const auto& kv : r) {
    const std::string key = kv.first.as<std::string>();
    if (std::find(std::begin(kRobotKeys), std::end(kRobotKeys), key) == std::end(kRobotKeys) &&
        std::find(extra_keys.begin(), extra_keys.end(), key) == extra_keys.end()) {
      std::string list;
      for (const char* k : kRobotKeys) list += (list.empty() ? "" : ", ") + std::string(k);
      f.Fail(prefix + key, "is not a known field (expected " + list + ")", kv.first);
    }
  }
  if (r["drive"]) {
    constexpr DriveType kDrives[] = {DriveType::kDiffDrive, DriveType::kOmni, DriveType::kUnicycle};
    d.drive = kDrives[f.Choice(r["drive"], prefix + "drive", {"diff_drive", "omni", "unicycle"})];
  }
  f.Read(r, "radius", prefix, d.radius, &YamlFields::Positive);
  f.Read(r, "height", prefix, d.height, &YamlFields::Positive);
  f.Read(r, "wheel_base", prefix, d.wheel_base, &YamlFields::Positive);
  f.Read(r, "wheel_radius", prefix, d.wheel_radius, &YamlFields::Positive);
  f.Read(r, "max_wheel_speed", prefix, d.max_wheel_speed, &YamlFields::Positive);
  f.Read(r, "max_wheel_accel", prefix, d.max_wheel_accel, &YamlFields::Positive);
  if (r["encoder_ticks_per_rev"]) {
    d.encoder_ticks_per_rev = f.Integer(r["encoder_ticks_per_rev"], prefix + "encoder_ticks_per_rev", 1, 1'000'000);
  }
  f.Read(r, "actuator_noise", prefix, d.actuator_noise, &YamlFields::NonNegative);
  f.Read(r, "encoder_noise", prefix, d.encoder_noise, &YamlFields::NonNegative);
  f.Read(r, "omni_wheel_distance", prefix, d.omni_wheel_distance, &YamlFields::Positive);
  if (r["omni_wheel_angles_deg"]) {
    const auto a = f.Numbers(r["omni_wheel_angles_deg"], prefix + "omni_wheel_angles_deg", 3, 3);
    for (size_t i = 0; i < 3; ++i) d.omni_wheel_angles[i] = a[i] * M_PI / 180.0;
  }
  f.Read(r, "max_speed", prefix, d.max_speed, &YamlFields::Positive);
  f.Read(r, "max_angular_speed", prefix, d.max_angular_speed, &YamlFields::Positive);
  f.Read(r, "max_accel", prefix, d.max_accel, &YamlFields::Positive);
  f.Read(r, "max_angular_accel", prefix, d.max_angular_accel, &YamlFields::Positive);
}

void ReadLaserDescription(const YamlFields& f, const YAML::Node& l, const std::string& prefix, LaserDescription& d) {
  f.ExpectMap(l, prefix.substr(0, prefix.size() - 1));
  f.CheckKeys(l, prefix.substr(0, prefix.size() - 1),
              {"type", "fov_deg", "range_min", "range_max", "beams", "rate_hz", "noise", "height"});
  if (l["fov_deg"]) d.fov = f.Positive(l["fov_deg"], prefix + "fov_deg") * M_PI / 180.0;
  f.Read(l, "range_min", prefix, d.range_min, &YamlFields::NonNegative);
  f.Read(l, "range_max", prefix, d.range_max, &YamlFields::Positive);
  if (l["beams"]) d.beams = f.Integer(l["beams"], prefix + "beams", 1, 100'000);
  f.Read(l, "rate_hz", prefix, d.rate, &YamlFields::Positive);
  f.Read(l, "noise", prefix, d.noise, &YamlFields::NonNegative);
  f.Read(l, "height", prefix, d.height, &YamlFields::NonNegative);
  if (d.fov > 2 * M_PI) f.Fail(prefix + "fov_deg", "must be at most 360", l["fov_deg"]);
  if (d.range_max <= d.range_min) f.Fail(prefix + "range_max", "must exceed " + prefix + "range_min", l);
}

void ReadDepthCameraDescription(const YamlFields& f, const YAML::Node& c, const std::string& prefix,
                                DepthCameraDescription& d) {
  const std::string field = prefix.substr(0, prefix.size() - 1);
  f.ExpectMap(c, field);
  f.CheckKeys(c, field,
              {"type", "resolution", "hfov_deg", "vfov_deg", "range_min", "range_max", "rate_hz", "mount", "tilt_deg",
               "noise", "holes"});
  if (c["resolution"]) {
    const auto r = f.Numbers(c["resolution"], prefix + "resolution", 2, 2);
    for (double v : r) {
      if (v < 2 || v > 4096 || v != std::floor(v))
        f.Fail(prefix + "resolution", "must be [width, height], whole pixels from 2 to 4096", c["resolution"]);
    }
    if (r[0] * r[1] > 1280.0 * 1024.0)
      f.Fail(prefix + "resolution", "must have no more pixels than 1280 x 1024", c["resolution"]);
    d.width = static_cast<int>(r[0]);
    d.height = static_cast<int>(r[1]);
  }
  auto angle = [&](const char* key, double& out, double max_deg) {
    if (!c[key]) return;
    const double deg = f.Positive(c[key], prefix + key);
    if (deg >= max_deg) f.Fail(prefix + key, "must be under " + std::to_string(static_cast<int>(max_deg)), c[key]);
    out = deg * M_PI / 180.0;
  };
  angle("hfov_deg", d.hfov, 170.0);
  angle("vfov_deg", d.vfov, 170.0);
  f.Read(c, "range_min", prefix, d.range_min, &YamlFields::NonNegative);
  f.Read(c, "range_max", prefix, d.range_max, &YamlFields::Positive);
  f.Read(c, "rate_hz", prefix, d.rate, &YamlFields::Positive);
  if (c["mount"]) {
    const auto m = f.Numbers(c["mount"], prefix + "mount", 3, 3);
    if (m[2] <= 0) f.Fail(prefix + "mount", "must be [x, y, z] with z (height above the floor) > 0", c["mount"]);
    d.mount_x = m[0];
    d.mount_y = m[1];
    d.mount_z = m[2];
  }
  if (c["tilt_deg"]) {
    const double deg = f.Number(c["tilt_deg"], prefix + "tilt_deg");
    if (!(std::abs(deg) < 90.0))
      f.Fail(prefix + "tilt_deg", "must be between -90 and 90 (degrees down)", c["tilt_deg"]);
    d.tilt = deg * M_PI / 180.0;
  }
  f.Read(c, "noise", prefix, d.noise, &YamlFields::NonNegative);
  if (c["holes"]) {
    d.holes = f.NonNegative(c["holes"], prefix + "holes");
    if (d.holes >= 1.0) f.Fail(prefix + "holes", "must be a share under 1", c["holes"]);
  }
  if (d.range_max <= d.range_min) f.Fail(prefix + "range_max", "must exceed " + prefix + "range_min", c);
}

Box ReadBox(const YamlFields& f, const YAML::Node& n, const std::string& field) {
  const auto b = f.Numbers(n, field, 4, 4);
  if (b[2] < b[0] || b[3] < b[1]) f.Fail(field, "must have x_min <= x_max and y_min <= y_max", n);
  return {{b[0], b[1]}, {b[2], b[3]}};
}

World ParseWorld(const std::string& yaml_text, const std::string& source, const std::string& base_dir) {
  return Parse(YamlFields(source), yaml_text, base_dir);
}

OccupancyGrid LoadMapFile(const std::string& path) {
  if (std::filesystem::path(path).extension() == ".map") return ParseMovingAiMap(ReadTextFile(path, "map file"), path);
  return LoadMapServerMap(path);
}

World LoadWorldFile(const std::string& path) {
  const std::string text = ReadTextFile(path, "world file");
  return ParseWorld(text, path, std::filesystem::path(path).parent_path().string());
}

World DefaultWorld() { return ParseWorld(navd_default_world_yaml, "<embedded warehouse>", "."); }

namespace {

enum class MapFileKind { kMovingAi, kMapServer, kWorld };

MapFileKind SniffMapFile(const std::string& text, const std::string& path) {
  if (text.rfind("type ", 0) == 0) return MapFileKind::kMovingAi;  // a MovingAI .map starts with its type line
  const YAML::Node doc = ParseYamlMapping(text, path);
  if (doc["image"]) return MapFileKind::kMapServer;
  if (doc["map"]) return MapFileKind::kWorld;
  throw Error(
      ErrorCode::kInvalidArgument,
      path + ": neither a map_server YAML (no 'image' field), a world file (no 'map' field) nor a MovingAI map");
}

// The known-free cell nearest the map's centre whose clearance fits a robot of `radius`.
Pose2 FreeSpotNearCentre(const OccupancyGrid& map, double radius, const std::string& path) {
  const DistanceField clearance(map, /*unknown_is_obstacle=*/true);
  const Point2 centre = map.origin() + 0.5 * Point2(map.width(), map.height()) * map.resolution();
  double best = std::numeric_limits<double>::infinity();
  Point2 spot;
  for (int y = 0; y < map.height(); ++y) {
    for (int x = 0; x < map.width(); ++x) {
      if (map.at({x, y}) != OccupancyGrid::kFree || clearance.at({x, y}) < radius + 0.05) continue;
      const Point2 p = map.CellCenter({x, y});
      const double d = (p - centre).squaredNorm();
      if (d < best) {
        best = d;
        spot = p;
      }
    }
  }
  if (!std::isfinite(best)) {
    throw Error(ErrorCode::kInvalidArgument,
                path + ": no free spot where a robot of radius " + std::to_string(radius).substr(0, 4) + " m fits");
  }
  return Pose2{spot.x(), spot.y(), 0.0};
}

}  // namespace

namespace {

// A map file already read and sniffed as `kind`; its name is the file's stem or the world's.
OccupancyGrid MapFromText(const std::string& text, const std::string& path, MapFileKind kind, std::string* name) {
  if (kind == MapFileKind::kWorld) {
    World w = ParseWorld(text, path, std::filesystem::path(path).parent_path().string());
    if (name) *name = w.name;
    return std::move(w.map);
  }
  if (name) *name = std::filesystem::path(path).stem().string();
  return kind == MapFileKind::kMovingAi ? ParseMovingAiMap(text, path) : LoadMapServerMap(path);
}

}  // namespace

OccupancyGrid LoadAnyMapFile(const std::string& path, std::string* name) {
  const std::string text = ReadTextFile(path, "map file");
  return MapFromText(text, path, SniffMapFile(text, path), name);
}

World LoadWorldOrMapFile(const std::string& path) {
  const std::string text = ReadTextFile(path, "world or map file");
  const MapFileKind kind = SniffMapFile(text, path);
  if (kind == MapFileKind::kWorld) return ParseWorld(text, path, std::filesystem::path(path).parent_path().string());
  World w;
  w.map = MapFromText(text, path, kind, &w.name);
  w.source = path;
  w.start = FreeSpotNearCentre(w.map, w.robot.radius, path);
  return w;
}

}  // namespace navd
