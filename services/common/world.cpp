#include "services/common/world.h"

#include <yaml-cpp/yaml.h>

#include <filesystem>

#include "services/common/error.h"
#include "services/common/map_server_format.h"
#include "services/common/movingai_format.h"
#include "services/common/text_file.h"
#include "services/common/yaml_document.h"

extern "C" const char navd_default_world_yaml[];

namespace navd {
namespace {

class WorldParser {
 public:
  explicit WorldParser(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void Fail(const std::string& field, const std::string& why) const {
    throw Error(ErrorCode::kInvalidArgument, source_ + ": field '" + field + "' " + why);
  }

  double Number(const YAML::Node& n, const std::string& field) const {
    try {
      const double v = n.as<double>();
      if (!std::isfinite(v)) Fail(field, "must be finite");
      return v;
    } catch (const YAML::Exception&) {
      Fail(field, "must be a number");
    }
  }
  double Positive(const YAML::Node& n, const std::string& field) const {
    const double v = Number(n, field);
    if (v <= 0) Fail(field, "must be positive");
    return v;
  }
  double NonNegative(const YAML::Node& n, const std::string& field) const {
    const double v = Number(n, field);
    if (v < 0) Fail(field, "must not be negative");
    return v;
  }
  // A misspelt key would otherwise be a silent default: name it, and what is allowed there.
  void CheckKeys(const YAML::Node& n, const std::string& where, std::initializer_list<const char*> allowed) const {
    for (const auto& kv : n) {
      if (!kv.first.IsScalar()) Fail(where.empty() ? "(top level)" : where, "has a key that is not a plain name");
      const std::string key = kv.first.as<std::string>();
      bool known = false;
      std::string list;
      for (const char* a : allowed) {
        known |= key == a;
        list += (list.empty() ? "" : ", ") + std::string(a);
      }
      if (!known) Fail(where.empty() ? key : where + "." + key, "is not a known field (expected " + list + ")");
    }
  }

  int Integer(const YAML::Node& n, const std::string& field, int min, int max) const {
    const double v = Number(n, field);
    if (v != std::floor(v) || v < min || v > max) {
      Fail(field, "must be a whole number from " + std::to_string(min) + " to " + std::to_string(max));
    }
    return static_cast<int>(v);
  }
  std::vector<double> Numbers(const YAML::Node& n, const std::string& field, size_t min, size_t max) const {
    if (!n.IsSequence() || n.size() < min || n.size() > max) {
      Fail(field, "must be a list of " + std::to_string(min) + (min == max ? "" : "-" + std::to_string(max)) + " numbers");
    }
    std::vector<double> out;
    for (size_t i = 0; i < n.size(); ++i) out.push_back(Number(n[i], field + "[" + std::to_string(i) + "]"));
    return out;
  }
  Pose2 PoseOf(const YAML::Node& n, const std::string& field) const {
    const auto v = Numbers(n, field, 2, 3);
    return {v[0], v[1], v.size() > 2 ? NormalizeAngle(v[2]) : 0.0};
  }

  OccupancyGrid InlineMap(const YAML::Node& m) const {
    CheckKeys(m, "map", {"resolution", "size", "origin", "boxes"});
    const double res = m["resolution"] ? Positive(m["resolution"], "map.resolution") : 0.05;
    if (!m["size"]) Fail("map.size", "is missing (expected [width_m, height_m])");
    const auto size = Numbers(m["size"], "map.size", 2, 2);
    const long long cells_x = std::llround(size[0] / res), cells_y = std::llround(size[1] / res);
    if (cells_x < 1 || cells_y < 1 || cells_x * cells_y > OccupancyGrid::kMaxCells) {
      Fail("map.size", "must span at least one cell and at most " + std::to_string(OccupancyGrid::kMaxCells) +
                           " cells at this resolution");
    }
    Point2 origin = Point2::Zero();
    if (m["origin"]) {
      const auto o = Numbers(m["origin"], "map.origin", 2, 3);
      origin = {o[0], o[1]};
    }
    OccupancyGrid grid(static_cast<int>(cells_x), static_cast<int>(cells_y), res, origin, OccupancyGrid::kFree);
    if (m["boxes"]) {
      if (!m["boxes"].IsSequence()) Fail("map.boxes", "must be a list of [x_min, y_min, x_max, y_max]");
      for (size_t i = 0; i < m["boxes"].size(); ++i) {
        const std::string f = "map.boxes[" + std::to_string(i) + "]";
        const auto b = Numbers(m["boxes"][i], f, 4, 4);
        if (b[2] < b[0] || b[3] < b[1]) Fail(f, "must have x_min <= x_max and y_min <= y_max");
        grid.FillBox({b[0], b[1]}, {b[2], b[3]});
      }
    }
    return grid;
  }

  World Parse(const std::string& text, const std::string& base_dir) const {
    const YAML::Node doc = ParseYamlMapping(text, source_);
    CheckKeys(doc, "", {"name", "map", "robot", "laser", "goals"});
    World w;
    w.source = source_;
    try {
      w.name = doc["name"] ? doc["name"].as<std::string>() : std::filesystem::path(source_).stem().string();
    } catch (const YAML::Exception&) {
      Fail("name", "must be a string");
    }
    const YAML::Node map = doc["map"];
    if (!map) Fail("map", "is missing (a map_server YAML path or an inline map)");
    if (map.IsScalar()) {
      std::filesystem::path p(map.as<std::string>());
      if (p.is_relative()) p = std::filesystem::path(base_dir) / p;
      w.map = LoadMapServerMap(p.string());
    } else if (map.IsMap()) {
      w.map = InlineMap(map);
    } else {
      Fail("map", "must be a file path or a mapping");
    }

    if (const YAML::Node r = doc["robot"]) {
      if (!r.IsMap()) Fail("robot", "must be a mapping");
      CheckKeys(r, "robot", {"start", "radius", "wheel_base", "wheel_radius", "max_wheel_speed", "max_wheel_accel",
                             "encoder_ticks_per_rev", "actuator_noise", "encoder_noise"});
      auto& d = w.robot;
      if (r["start"]) w.start = PoseOf(r["start"], "robot.start");
      if (r["radius"]) d.radius = Positive(r["radius"], "robot.radius");
      if (r["wheel_base"]) d.wheel_base = Positive(r["wheel_base"], "robot.wheel_base");
      if (r["wheel_radius"]) d.wheel_radius = Positive(r["wheel_radius"], "robot.wheel_radius");
      if (r["max_wheel_speed"]) d.max_wheel_speed = Positive(r["max_wheel_speed"], "robot.max_wheel_speed");
      if (r["max_wheel_accel"]) d.max_wheel_accel = Positive(r["max_wheel_accel"], "robot.max_wheel_accel");
      if (r["encoder_ticks_per_rev"]) {
        d.encoder_ticks_per_rev = Integer(r["encoder_ticks_per_rev"], "robot.encoder_ticks_per_rev", 1, 1'000'000);
      }
      if (r["actuator_noise"]) d.actuator_noise = NonNegative(r["actuator_noise"], "robot.actuator_noise");
      if (r["encoder_noise"]) d.encoder_noise = NonNegative(r["encoder_noise"], "robot.encoder_noise");
    }
    if (const YAML::Node l = doc["laser"]) {
      if (!l.IsMap()) Fail("laser", "must be a mapping");
      CheckKeys(l, "laser", {"fov_deg", "range_min", "range_max", "beams", "rate_hz", "noise"});
      auto& d = w.laser;
      if (l["fov_deg"]) d.fov = Positive(l["fov_deg"], "laser.fov_deg") * M_PI / 180.0;
      if (l["range_min"]) d.range_min = NonNegative(l["range_min"], "laser.range_min");
      if (l["range_max"]) d.range_max = Positive(l["range_max"], "laser.range_max");
      if (l["beams"]) d.beams = Integer(l["beams"], "laser.beams", 1, 100'000);
      if (l["rate_hz"]) d.rate = Positive(l["rate_hz"], "laser.rate_hz");
      if (l["noise"]) d.noise = NonNegative(l["noise"], "laser.noise");
      if (d.fov > 2 * M_PI) Fail("laser.fov_deg", "must be at most 360");
      if (d.range_max <= d.range_min) Fail("laser.range_max", "must exceed laser.range_min");
    }
    if (const YAML::Node g = doc["goals"]) {
      if (!g.IsSequence()) Fail("goals", "must be a list of [x, y] or [x, y, theta]");
      for (size_t i = 0; i < g.size(); ++i) w.goals.push_back(PoseOf(g[i], "goals[" + std::to_string(i) + "]"));
    }
    if (!w.map.ContainsPoint(w.start.translation())) Fail("robot.start", "lies outside the map");
    if (w.map.DiscHitsObstacle(w.start.translation(), w.robot.radius)) {
      Fail("robot.start", "puts the robot (radius " + std::to_string(w.robot.radius).substr(0, 4) +
                              " m) inside or against an obstacle");
    }
    return w;
  }

 private:
  std::string source_;
};

}  // namespace

World ParseWorld(const std::string& yaml_text, const std::string& source, const std::string& base_dir) {
  return WorldParser(source).Parse(yaml_text, base_dir);
}

World LoadWorldFile(const std::string& path) {
  const std::string text = ReadTextFile(path, "world file");
  return ParseWorld(text, path, std::filesystem::path(path).parent_path().string());
}

World DefaultWorld() { return ParseWorld(navd_default_world_yaml, "<embedded warehouse>", "."); }

OccupancyGrid LoadAnyMapFile(const std::string& path, std::string* name) {
  const std::string text = ReadTextFile(path, "map file");
  if (text.rfind("type ", 0) == 0) {  // a MovingAI .map starts with its type line
    if (name) *name = std::filesystem::path(path).stem().string();
    return ParseMovingAiMap(text, path);
  }
  const YAML::Node doc = ParseYamlMapping(text, path);
  if (doc["image"]) {
    if (name) *name = std::filesystem::path(path).stem().string();
    return LoadMapServerMap(path);
  }
  if (doc["map"]) {
    World w = ParseWorld(text, path, std::filesystem::path(path).parent_path().string());
    if (name) *name = w.name;
    return std::move(w.map);
  }
  throw Error(ErrorCode::kInvalidArgument,
              path + ": neither a map_server YAML (no 'image' field), a world file (no 'map' field) nor a MovingAI map");
}

}  // namespace navd
