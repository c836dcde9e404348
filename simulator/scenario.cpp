#include "simulator/scenario.h"

#include <filesystem>
#include <memory>
#include <random>
#include <regex>
#include <set>

#include "services/common/distance_field.h"
#include "services/common/error.h"
#include "services/common/polygon.h"
#include "services/common/text_file.h"
#include "services/common/world_fields.h"
#include "services/common/yaml_document.h"
#include "services/common/yaml_fields.h"

namespace navd::sim {
namespace {

std::string Index(const std::string& list, size_t i) { return list + "[" + std::to_string(i) + "]"; }

void ReadRangeArray(const YamlFields& f, const YAML::Node& n, const std::string& prefix, RangeArrayDescription& d) {
  f.CheckKeys(n, prefix.substr(0, prefix.size() - 1),
              {"type", "angles_deg", "mount_radius", "cone_deg", "rays_per_cone", "range_min", "range_max", "noise",
               "rate_hz"});
  if (n["angles_deg"]) {
    d.angles.clear();
    if (!n["angles_deg"].IsSequence() || n["angles_deg"].size() == 0) {
      f.Fail(prefix + "angles_deg", "must be a non-empty list of angles", n["angles_deg"]);
    }
    for (size_t i = 0; i < n["angles_deg"].size(); ++i) {
      d.angles.push_back(f.Number(n["angles_deg"][i], Index(prefix + "angles_deg", i)) * M_PI / 180.0);
    }
  }
  f.Read(n, "mount_radius", prefix, d.mount_radius, &YamlFields::NonNegative);
  if (n["cone_deg"]) d.cone = f.NonNegative(n["cone_deg"], prefix + "cone_deg") * M_PI / 180.0;
  if (n["rays_per_cone"]) d.rays_per_cone = f.Integer(n["rays_per_cone"], prefix + "rays_per_cone", 1, 100);
  f.Read(n, "range_min", prefix, d.range_min, &YamlFields::NonNegative);
  f.Read(n, "range_max", prefix, d.range_max, &YamlFields::Positive);
  f.Read(n, "noise", prefix, d.noise, &YamlFields::NonNegative);
  f.Read(n, "rate_hz", prefix, d.rate, &YamlFields::Positive);
  if (d.range_max <= d.range_min) f.Fail(prefix + "range_max", "must exceed " + prefix + "range_min", n);
}

void ReadSensors(const YamlFields& f, const YAML::Node& list, const std::string& prefix, const World& world,
                 RobotSpec& r) {
  f.ExpectSequence(list, prefix + "sensors", "sensors ({type: laser|sonar|ir|camera|bumper|encoders|people, ...})");
  r.laser.reset();
  r.camera.reset();
  r.people.reset();
  r.sonar.reset();
  r.ir.reset();
  r.bumper = r.encoders = false;
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node s = list[i];
    const std::string field = Index(prefix + "sensors", i);
    if (!s.IsMap() || !s["type"]) f.Fail(field, "must be a mapping with a 'type'", s);
    const std::string type = f.String(s["type"], field + ".type");
    if (type == "laser") {
      LaserDescription l = world.laser;
      ReadLaserDescription(f, s, field + ".", l);
      r.laser = l;
    } else if (type == "camera") {
      DepthCameraDescription d = world.camera.value_or(DepthCameraDescription{});
      ReadDepthCameraDescription(f, s, field + ".", d);
      r.camera = d;
    } else if (type == "sonar") {
      RangeArrayDescription d = PioneerSonarRing(r.body.radius);
      ReadRangeArray(f, s, field + ".", d);
      r.sonar = d;
    } else if (type == "ir") {
      RangeArrayDescription d = Gp2d12Triple(r.body.radius);
      ReadRangeArray(f, s, field + ".", d);
      r.ir = d;
    } else if (type == "bumper") {
      f.CheckKeys(s, field, {"type", "rate_hz"});
      r.bumper = true;
      f.Read(s, "rate_hz", field + ".", r.bumper_rate, &YamlFields::Positive);
    } else if (type == "encoders") {
      f.CheckKeys(s, field, {"type", "rate_hz"});
      r.encoders = true;
      f.Read(s, "rate_hz", field + ".", r.encoder_rate, &YamlFields::Positive);
    } else if (type == "people") {
      f.CheckKeys(s, field, {"type", "range_max", "fov_deg", "rate_hz", "position_noise", "velocity_noise"});
      PeopleSensorDescription d;
      double fov_deg = d.fov * 180.0 / M_PI;
      f.Read(s, "range_max", field + ".", d.range_max, &YamlFields::Positive);
      f.Read(s, "fov_deg", field + ".", fov_deg, &YamlFields::Positive);
      if (fov_deg > 360.0) f.Fail(field + ".fov_deg", "must be at most 360", s["fov_deg"]);
      d.fov = fov_deg * M_PI / 180.0;
      f.Read(s, "rate_hz", field + ".", d.rate, &YamlFields::Positive);
      f.Read(s, "position_noise", field + ".", d.position_noise, &YamlFields::NonNegative);
      f.Read(s, "velocity_noise", field + ".", d.velocity_noise, &YamlFields::NonNegative);
      r.people = d;
    } else {
      f.Fail(field + ".type",
             "is not a known sensor type '" + type + "' (expected laser, sonar, ir, camera, bumper, encoders, people)",
             s["type"]);
    }
  }
}

Box AreaOf(const YamlFields& f, const YAML::Node& n, const std::string& field, const World& world) {
  if (n.IsScalar()) {
    const std::string name = n.as<std::string>();
    const auto it = world.regions.find(name);
    if (it == world.regions.end()) f.Fail(field, "names region '" + name + "', which the world does not define", n);
    return it->second;
  }
  return ReadBox(f, n, field);
}

CrowdDescription ReadCrowd(const YamlFields& f, const YAML::Node& n, const World& world) {
  f.ExpectMap(n, "people");
  f.CheckKeys(n, "people",
              {"area", "mode", "initial", "max", "arrival_rate", "speed", "radius", "goal_ahead", "goal_period",
               "brownian", "spawn_clearance"});
  CrowdDescription c;
  if (!n["area"]) f.Fail("people.area", "is missing (a region name or [x_min, y_min, x_max, y_max])", n);
  c.area = AreaOf(f, n["area"], "people.area", world);
  if (n["mode"]) {
    c.street = f.Choice(n["mode"], "people.mode", {"street", "room"}) == 0;
  }
  if (n["initial"]) {
    const auto v = f.Numbers(n["initial"], "people.initial", 1, 2);
    for (double x : v) {
      if (x < 0 || x != std::floor(x) || x > 1000)
        f.Fail("people.initial", "must be whole numbers from 0 to 1000", n["initial"]);
    }
    c.initial_min = static_cast<int>(v[0]);
    c.initial_max = static_cast<int>(v.size() > 1 ? v[1] : v[0]);
    if (c.initial_max < c.initial_min) f.Fail("people.initial", "must be [min, max] with min <= max", n["initial"]);
  }
  if (n["max"]) c.max_people = f.Integer(n["max"], "people.max", 0, 1000);
  f.Read(n, "arrival_rate", "people.", c.arrival_rate, &YamlFields::NonNegative);
  if (n["speed"]) {
    const auto v = f.Numbers(n["speed"], "people.speed", 2, 2);
    if (v[0] <= 0 || v[1] < 0) f.Fail("people.speed", "must be [mean > 0, std-dev >= 0] in m/s", n["speed"]);
    c.speed_mean = v[0];
    c.speed_std = v[1];
  }
  f.Read(n, "radius", "people.", c.radius, &YamlFields::Positive);
  f.Read(n, "goal_ahead", "people.", c.goal_ahead, &YamlFields::Positive);
  if (n["goal_period"]) {
    const auto v = f.Numbers(n["goal_period"], "people.goal_period", 2, 2);
    if (v[0] <= 0 || v[1] < v[0])
      f.Fail("people.goal_period", "must be [min > 0, max >= min] in seconds", n["goal_period"]);
    c.goal_period_min = v[0];
    c.goal_period_max = v[1];
  }
  f.Read(n, "brownian", "people.", c.brownian, &YamlFields::NonNegative);
  f.Read(n, "spawn_clearance", "people.", c.spawn_clearance, &YamlFields::NonNegative);
  return c;
}

// Fills the box into the truth; returns the cells it newly walled.
std::vector<CellIndex> FillFresh(OccupancyGrid& truth, const Point2& min, const Point2& max) {
  const CellIndex lo = truth.CellOf(min), hi = truth.CellOf(max);
  std::vector<CellIndex> fresh;
  for (int y = std::max(lo.y, 0); y <= std::min(hi.y, truth.height() - 1); ++y)
    for (int x = std::max(lo.x, 0); x <= std::min(hi.x, truth.width() - 1); ++x)
      if (!truth.IsOccupied({x, y})) fresh.push_back({x, y});
  truth.FillBox(min, max);
  std::vector<CellIndex> walled;
  for (const CellIndex& c : fresh)
    if (truth.IsOccupied(c)) walled.push_back(c);
  return walled;
}

// Fills the box into the truth; a glass one's newly walled cells are remembered as seen through.
void FillHidden(Scenario& s, const Point2& min, const Point2& max, bool glass) {
  if (!glass) {
    s.truth.FillBox(min, max);
    return;
  }
  const std::vector<CellIndex> walled = FillFresh(s.truth, min, max);
  s.see_through.insert(s.see_through.end(), walled.begin(), walled.end());
}

// hidden_obstacles.solids: {type: table|box|shelf|solid, box: [x_min, y_min, x_max, y_max], ...}.
// A table is four 5 cm legs at the box's corners under a 4 cm top at `height`; a box stands on
// the floor up to `height`; a shelf or a solid fills `z: [z_min, z_max]`.
void ReadSolids(const YamlFields& f, const YAML::Node& list, Scenario& s) {
  f.ExpectSequence(list, "hidden_obstacles.solids",
                   "{type: table|box|shelf|solid, box: [x_min, y_min, x_max, y_max], height or z: [z_min, z_max]}");
  constexpr double kLeg = 0.05, kTop = 0.04;  // m
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node n = list[i];
    const std::string field = Index("hidden_obstacles.solids", i);
    f.ExpectMap(n, field);
    f.CheckKeys(n, field, {"type", "box", "height", "z"});
    const size_t type = n["type"] ? f.Choice(n["type"], field + ".type", {"table", "box", "shelf", "solid"}) : 3;
    if (!n["box"]) f.Fail(field + ".box", "is missing ([x_min, y_min, x_max, y_max])", n);
    const Box box = ReadBox(f, n["box"], field + ".box");
    const Point2 map_min = s.truth.origin(), map_max = map_min + Point2(s.truth.size_x(), s.truth.size_y());
    if (box.max.x() < map_min.x() || box.max.y() < map_min.y() || box.min.x() > map_max.x() ||
        box.min.y() > map_max.y())
      f.Fail(field + ".box",
             "lies outside the map, which spans " + FormatPoint(map_min) + " to " + FormatPoint(map_max), n["box"]);
    if (type <= 1) {
      if (!n["height"] || n["z"]) f.Fail(field, "a table or a box needs a height (m) and no z", n);
      const double h = f.Positive(n["height"], field + ".height");
      if (type == 1) {
        s.solids.push_back({box, 0.0, h});
        continue;
      }
      if (h <= kTop || box.max.x() - box.min.x() < 2 * kLeg || box.max.y() - box.min.y() < 2 * kLeg)
        f.Fail(field, "a table must be higher than its 4 cm top and at least 10 cm across", n);
      s.solids.push_back({box, h - kTop, h});
      for (const double x : {box.min.x(), box.max.x() - kLeg})
        for (const double y : {box.min.y(), box.max.y() - kLeg})
          s.solids.push_back({{{x, y}, {x + kLeg, y + kLeg}}, 0.0, h - kTop});
    } else {
      if (!n["z"] || n["height"]) f.Fail(field, "a shelf or a solid needs z: [z_min, z_max] (m) and no height", n);
      const auto z = f.Numbers(n["z"], field + ".z", 2, 2);
      if (!(z[0] >= 0.0 && z[1] > z[0])) f.Fail(field + ".z", "must be [z_min >= 0, z_max > z_min] in metres", n["z"]);
      s.solids.push_back({box, z[0], z[1]});
    }
  }
}

// The solids into the truth: those that reach below the tallest robot's top; the cells they alone
// fill are remembered, and those of solids that miss the lasers' plane are seen through. Solids
// the lasers see go in first, so a table's top does not hide its legs from them.
void FillSolids(Scenario& s) {
  double tallest = 0.0, laser_height = -1.0;
  for (const RobotSpec& r : s.robots) {
    tallest = std::max(tallest, r.body.height);
    if (r.laser && laser_height < 0.0) laser_height = r.laser->height;
  }
  auto seen_by_laser = [&](const Solid& solid) { return solid.z_min <= laser_height && laser_height <= solid.z_max; };
  for (const bool laser_pass : {true, false}) {
    for (const Solid& solid : s.solids) {
      if (seen_by_laser(solid) != laser_pass || solid.z_min >= tallest) continue;
      const std::vector<CellIndex> walled = FillFresh(s.truth, solid.box.min, solid.box.max);
      s.solid_cells.insert(s.solid_cells.end(), walled.begin(), walled.end());
      if (!laser_pass) s.see_through.insert(s.see_through.end(), walled.begin(), walled.end());
    }
  }
}

// Seed 004's "randomly distributed small obstacles" unknown to the robot: squares of random size,
// each at least `clearance` from walls, other obstacles, robots and targets, so no passage the
// robot needs is closed; with `glass: true` they are panes the laser sees through.
int PlaceRandomObstacles(const YamlFields& f, const YAML::Node& n, Scenario& s, std::mt19937_64& rng) {
  f.CheckKeys(n, "hidden_obstacles.random", {"count", "size", "area", "clearance", "glass"});
  const bool glass = n["glass"] && f.Bool(n["glass"], "hidden_obstacles.random.glass");
  if (!n["count"]) f.Fail("hidden_obstacles.random.count", "is missing", n);
  const int count = f.Integer(n["count"], "hidden_obstacles.random.count", 0, 10000);
  double size_min = 0.10, size_max = 0.30, clearance = 0.8;
  if (n["size"]) {
    const auto v = f.Numbers(n["size"], "hidden_obstacles.random.size", 2, 2);
    if (v[0] <= 0 || v[1] < v[0])
      f.Fail("hidden_obstacles.random.size", "must be [min > 0, max >= min] in metres", n["size"]);
    size_min = v[0];
    size_max = v[1];
  }
  f.Read(n, "clearance", "hidden_obstacles.random.", clearance, &YamlFields::NonNegative);
  Box area{s.truth.origin(), s.truth.origin() + Point2(s.truth.size_x(), s.truth.size_y())};
  if (n["area"]) area = AreaOf(f, n["area"], "hidden_obstacles.random.area", s.world);
  std::uniform_real_distribution<double> ux(area.min.x(), area.max.x()), uy(area.min.y(), area.max.y());
  std::uniform_real_distribution<double> usize(size_min, size_max);
  int placed = 0;
  auto field = std::make_unique<DistanceField>(s.truth);
  for (int tries = 0; placed < count && tries < 1000 * (count + 1); ++tries) {
    const Point2 c(ux(rng), uy(rng));
    const double half = usize(rng) / 2;
    const CellIndex cell = s.truth.CellOf(c);
    if (!s.truth.Contains(cell) || field->at(cell) < half * M_SQRT2 + clearance) continue;
    bool near = false;
    for (const auto& r : s.robots)
      near |= Distance(r.start.translation(), c) < half * M_SQRT2 + clearance + r.body.radius;
    for (const auto& t : s.targets) near |= Distance(t, c) < half * M_SQRT2 + clearance;
    if (near) continue;
    FillHidden(s, c - Point2(half, half), c + Point2(half, half), glass);
    field = std::make_unique<DistanceField>(s.truth);  // keeps the next ones clear of this one
    ++placed;
  }
  if (placed < count) {
    f.Fail("hidden_obstacles.random.count",
           "asks for " + std::to_string(count) + " obstacles but only " + std::to_string(placed) +
               " fit with the clearance",
           n["count"]);
  }
  return placed;
}

// `world:`: a world file (relative to the scenario) or "default".
World ReadWorld(const YamlFields& f, const YAML::Node& doc, const std::string& base_dir) {
  if (!doc["world"]) f.Fail("world", "is missing (a world file path, relative to the scenario, or 'default')", doc);
  const YAML::Node w = doc["world"];
  if (!w.IsScalar()) f.Fail("world", "must be a world file path or 'default'", w);
  const std::string world_path = w.as<std::string>();
  if (world_path == "default") return DefaultWorld();
  std::filesystem::path p(world_path);
  if (p.is_relative()) p = std::filesystem::path(base_dir) / p;
  return LoadWorldFile(p.string());
}

// `robots:`: each the world's robot with what it overrides, named (several need names), at its
// start (the first may take the world's), with the world's sensors unless it lists its own.
std::vector<RobotSpec> ReadRobots(const YamlFields& f, const YAML::Node& robots, const World& world) {
  f.ExpectSequence(robots, "robots", "robots");
  if (robots.size() == 0) f.Fail("robots", "must list at least one robot", robots);
  std::vector<RobotSpec> out;
  std::set<std::string> names;
  const std::regex valid_name("[A-Za-z][A-Za-z0-9_]*");
  for (size_t i = 0; i < robots.size(); ++i) {
    const YAML::Node r = robots[i];
    const std::string field = Index("robots", i);
    f.ExpectMap(r, field);
    RobotSpec spec;
    spec.body = world.robot;
    ReadRobotDescription(f, r, field + ".", spec.body, {"name", "sensors"});
    if (r["name"]) spec.name = f.String(r["name"], field + ".name");
    if (robots.size() > 1 && spec.name.empty()) f.Fail(field + ".name", "is required when there are several robots", r);
    if (!spec.name.empty() && !std::regex_match(spec.name, valid_name)) {
      f.Fail(field + ".name", "must be a topic name (a letter, then letters, digits or _)", r["name"]);
    }
    if (!names.insert(spec.name).second) f.Fail(field + ".name", "repeats robot name '" + spec.name + "'", r["name"]);
    if (r["start"]) {
      spec.start = f.PoseOf(r["start"], field + ".start");
    } else if (i == 0) {
      spec.start = world.start;
    } else {
      f.Fail(field + ".start", "is missing ([x, y, theta] in metres and radians)", r);
    }
    spec.laser = world.laser;
    spec.camera = world.camera;
    spec.bumper = spec.encoders = true;
    if (r["sensors"]) ReadSensors(f, r["sensors"], field + ".", world, spec);
    out.push_back(spec);
  }
  return out;
}

std::vector<Door> ReadDoors(const YamlFields& f, const YAML::Node& doors) {
  f.ExpectSequence(doors, "doors", "{name, box, closed}");
  std::vector<Door> out;
  for (size_t i = 0; i < doors.size(); ++i) {
    const std::string field = Index("doors", i);
    f.ExpectMap(doors[i], field);
    f.CheckKeys(doors[i], field, {"name", "box", "closed"});
    Door d;
    if (!doors[i]["name"] || !doors[i]["box"]) f.Fail(field, "needs a name and a box", doors[i]);
    d.name = f.String(doors[i]["name"], field + ".name");
    d.box = ReadBox(f, doors[i]["box"], field + ".box");
    if (doors[i]["closed"]) d.closed = f.Bool(doors[i]["closed"], field + ".closed");
    out.push_back(d);
  }
  return out;
}

// `hidden_obstacles:` into the scenario's truth (boxes, glass, discs, solids, then the random ones
// clear of those), counted in s.hidden_obstacles.
void ReadHiddenObstacles(const YamlFields& f, const YAML::Node& h, Scenario& s, std::mt19937_64& rng) {
  f.ExpectMap(h, "hidden_obstacles");
  f.CheckKeys(h, "hidden_obstacles", {"boxes", "discs", "glass", "solids", "random"});
  if (h["boxes"]) {
    f.ExpectSequence(h["boxes"], "hidden_obstacles.boxes", "[x_min, y_min, x_max, y_max]");
    for (size_t i = 0; i < h["boxes"].size(); ++i) {
      const Box b = ReadBox(f, h["boxes"][i], Index("hidden_obstacles.boxes", i));
      s.truth.FillBox(b.min, b.max);
      ++s.hidden_obstacles;
    }
  }
  if (h["glass"]) {
    f.ExpectSequence(h["glass"], "hidden_obstacles.glass", "[x_min, y_min, x_max, y_max]");
    for (size_t i = 0; i < h["glass"].size(); ++i) {
      const Box b = ReadBox(f, h["glass"][i], Index("hidden_obstacles.glass", i));
      FillHidden(s, b.min, b.max, true);
      ++s.hidden_obstacles;
    }
  }
  if (h["discs"]) {
    f.ExpectSequence(h["discs"], "hidden_obstacles.discs", "[x, y, radius]");
    for (size_t i = 0; i < h["discs"].size(); ++i) {
      const std::string field = Index("hidden_obstacles.discs", i);
      const auto v = f.Numbers(h["discs"][i], field, 3, 3);
      if (v[2] <= 0) f.Fail(field, "must have a positive radius", h["discs"][i]);
      FillPolygon(s.truth, [&] {
        Polygon p;
        for (int k = 0; k < 16; ++k)
          p.push_back({v[0] + v[2] * std::cos(k * M_PI / 8), v[1] + v[2] * std::sin(k * M_PI / 8)});
        return p;
      }());
      ++s.hidden_obstacles;
    }
  }
  if (h["solids"]) {
    ReadSolids(f, h["solids"], s);
    FillSolids(s);
    s.hidden_obstacles += static_cast<int>(h["solids"].size());
  }
  if (h["random"]) s.hidden_obstacles += PlaceRandomObstacles(f, h["random"], s, rng);
}

// `moving_obstacles:`, each on a loop clear of the truth's walls (or it would stall forever).
std::vector<MovingObstacleDescription> ReadMovingObstacles(const YamlFields& f, const YAML::Node& m,
                                                           const OccupancyGrid& truth) {
  f.ExpectSequence(m, "moving_obstacles", "{name, radius, speed, loop}");
  std::vector<MovingObstacleDescription> out;
  for (size_t i = 0; i < m.size(); ++i) {
    const std::string field = Index("moving_obstacles", i);
    f.ExpectMap(m[i], field);
    f.CheckKeys(m[i], field, {"name", "radius", "speed", "loop", "patience"});
    MovingObstacleDescription d;
    d.name = m[i]["name"] ? f.String(m[i]["name"], field + ".name") : "obstacle" + std::to_string(i + 1);
    f.Read(m[i], "radius", field + ".", d.radius, &YamlFields::Positive);
    f.Read(m[i], "speed", field + ".", d.speed, &YamlFields::NonNegative);
    f.Read(m[i], "patience", field + ".", d.patience, &YamlFields::NonNegative);
    if (!m[i]["loop"]) f.Fail(field + ".loop", "is missing (a list of at least 2 [x, y] points)", m[i]);
    d.loop = f.Points(m[i]["loop"], field + ".loop", 2);
    for (size_t k = 0; k < d.loop.size(); ++k) {
      const Point2 a = d.loop[k], b = d.loop[(k + 1) % d.loop.size()];
      const int n = std::max(1, static_cast<int>(Distance(a, b) / (truth.resolution() / 2)));
      for (int j = 0; j <= n; ++j) {
        const Point2 p = a + (b - a) * (static_cast<double>(j) / n);
        if (truth.DiscHitsObstacle(p, d.radius)) {
          f.Fail(Index(field + ".loop", k), "runs into a wall at " + FormatPoint(p), m[i]["loop"][k]);
        }
      }
    }
    out.push_back(d);
  }
  return out;
}

// Every robot must start in free space, clear of the others.
void CheckRobotStarts(const YamlFields& f, const YAML::Node& doc, const Scenario& s) {
  for (size_t i = 0; i < s.robots.size(); ++i) {
    const auto& r = s.robots[i];
    const YAML::Node at = doc["robots"] ? doc["robots"][i] : doc["world"];
    if (s.truth.DiscHitsObstacle(r.start.translation(), r.body.radius)) {
      f.Fail(Index("robots", i) + ".start",
             "puts the robot inside or against a wall at " + FormatPoint(r.start.translation()), at);
    }
    for (size_t j = 0; j < i; ++j) {
      if (Distance(r.start.translation(), s.robots[j].start.translation()) < r.body.radius + s.robots[j].body.radius) {
        f.Fail(Index("robots", i) + ".start", "overlaps robot '" + s.robots[j].name + "'", at);
      }
    }
  }
}

Scenario Parse(const YamlFields& f, const std::string& text, const std::string& base_dir) {
  const YAML::Node doc = ParseYamlMapping(text, f.source());
  f.CheckKeys(
      doc, "",
      {"name", "world", "seed", "targets", "hidden_obstacles", "doors", "robots", "moving_obstacles", "people"});
  Scenario s;
  s.source = f.source();
  s.name = doc["name"] ? f.String(doc["name"], "name") : std::filesystem::path(f.source()).stem().string();
  s.world = ReadWorld(f, doc, base_dir);
  s.truth = s.world.map;
  if (doc["seed"]) {
    s.seed = static_cast<uint64_t>(f.Integer(doc["seed"], "seed", 0, 2'000'000'000));
  }
  if (doc["targets"]) s.targets = f.Points(doc["targets"], "targets", 1);
  s.robots = doc["robots"] ? ReadRobots(f, doc["robots"], s.world) : ScenarioFromWorld(s.world).robots;
  // Doors and hidden obstacles change only the truth; doors are filled in once the hidden
  // obstacles are, so that opening one can restore what lies under it.
  if (const YAML::Node doors = doc["doors"]) s.doors = ReadDoors(f, doors);
  std::mt19937_64 rng(s.seed * 7919 + 17);
  if (const YAML::Node h = doc["hidden_obstacles"]) ReadHiddenObstacles(f, h, s, rng);
  s.fixed_truth = s.truth;
  s.truth = TruthWithDoors(s.fixed_truth, s.doors);
  if (const YAML::Node m = doc["moving_obstacles"]) s.moving_obstacles = ReadMovingObstacles(f, m, s.truth);
  if (doc["people"]) s.crowd = ReadCrowd(f, doc["people"], s.world);
  CheckRobotStarts(f, doc, s);
  return s;
}

}  // namespace

OccupancyGrid TruthWithDoors(const OccupancyGrid& fixed, const std::vector<Door>& doors) {
  OccupancyGrid truth = fixed;
  for (const Door& d : doors) {
    if (d.closed) truth.FillBox(d.box.min, d.box.max);
  }
  return truth;
}

OccupancyGrid WithCellsFree(const OccupancyGrid& truth, const std::vector<CellIndex>& cells) {
  OccupancyGrid view = truth;
  for (const CellIndex& c : cells) view.set(c, OccupancyGrid::kFree);
  return view;
}

Scenario ScenarioFromWorld(World world) {
  Scenario s;
  s.name = world.name;
  s.source = world.source;
  s.truth = world.map;
  s.fixed_truth = world.map;
  RobotSpec r;
  r.start = world.start;
  r.body = world.robot;
  r.laser = world.laser;
  r.camera = world.camera;
  r.bumper = r.encoders = true;
  s.robots.push_back(r);
  s.world = std::move(world);
  return s;
}

Scenario ParseScenario(const std::string& yaml_text, const std::string& source, const std::string& base_dir) {
  return Parse(YamlFields(source), yaml_text, base_dir);
}

Scenario LoadScenarioFile(const std::string& path) {
  const std::string text = ReadTextFile(path, "scenario file");
  return ParseScenario(text, path, std::filesystem::path(path).parent_path().string());
}

}  // namespace navd::sim
