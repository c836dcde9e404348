#pragma once
// A world file: the map plus the robot that lives in it. Shared by navsim (which simulates it) and
// navd (which plans on its map and starts from its robot pose). Units: metres, radians, seconds,
// map frame. See worlds/warehouse.yaml for the format.
#include <string>
#include <vector>

#include "services/common/occupancy_grid.h"
#include "services/common/pose2.h"

namespace navd {

// Differential-drive geometry and limits (seed 000's robot by default).
struct RobotDescription {
  double radius = 0.20;            // m, the robot is a disc
  double wheel_base = 0.33;        // m, distance between the drive wheels
  double wheel_radius = 0.05;      // m
  double max_wheel_speed = 0.5;    // m/s at the rim
  double max_wheel_accel = 2.0;    // m/s^2 at the rim
  int encoder_ticks_per_rev = 1024;
  double actuator_noise = 0.02;    // relative std-dev of each wheel's achieved speed
  double encoder_noise = 0.005;    // relative std-dev of each wheel's measured travel (slip)
};

// A laser range finder like the Hokuyo URG-04LX of seed 000.
struct LaserDescription {
  double fov = 240.0 * M_PI / 180.0;  // rad, centred on the robot's heading
  double range_min = 0.02;            // m
  double range_max = 4.0;             // m
  int beams = 683;
  double rate = 10.0;                 // Hz
  double noise = 0.01;                // m, std-dev of range noise
};

struct World {
  std::string name;
  std::string source;              // file path, or "<embedded>"
  OccupancyGrid map;
  Pose2 start;                     // robot start pose in the map frame
  RobotDescription robot;
  LaserDescription laser;
  std::vector<Pose2> goals;        // named demo goals, in order
};

// Parses a world YAML. `base_dir` resolves a map file path given in it. Throws navd::Error naming
// the field on bad input.
World ParseWorld(const std::string& yaml_text, const std::string& source, const std::string& base_dir);
World LoadWorldFile(const std::string& path);
// The embedded default world (worlds/warehouse.yaml, compiled in).
World DefaultWorld();

// Loads a world YAML (has a `map:` key), a map_server YAML (has `image:`) or a MovingAI `.map`
// (starts with `type`), as navd's --map and LoadMap accept. Returns the map and its name.
OccupancyGrid LoadAnyMapFile(const std::string& path, std::string* name = nullptr);

}  // namespace navd
