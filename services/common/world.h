#pragma once
// A world file: the map plus the robot that lives in it. Shared by navsim (which simulates it) and
// navd (which plans on its map and starts from its robot pose). Units: metres, radians, seconds,
// map frame. See worlds/warehouse.yaml for the format.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "services/common/occupancy_grid.h"
#include "services/common/polygon.h"
#include "services/common/pose2.h"

namespace navd {

// How the robot's wheels move it (book chapter 1 and chapter 7).
enum class DriveType {
  kDiffDrive,  // two drive wheels: v, omega (Eqs. 7-10)
  kOmni,       // three omni wheels at angles alpha_i, distance R from the centre (Eq. 12)
  kUnicycle,   // driven by linear and angular accelerations (chapter 7, Eqs. 9-10)
};
const char* DriveTypeName(DriveType type);

// The robot's geometry and limits (seed 000's differential-drive robot by default).
struct RobotDescription {
  DriveType drive = DriveType::kDiffDrive;
  double radius = 0.20;  // m, the robot is a disc
  // m from the floor to the robot's top: a solid of the world whose underside is this high or
  // higher (a table top, a shelf) passes over the robot; anything lower is in its way.
  double height = 0.5;
  double wheel_base = 0.33;      // m, distance between the drive wheels (diff drive, unicycle)
  double wheel_radius = 0.05;    // m
  double max_wheel_speed = 0.5;  // m/s at the rim
  double max_wheel_accel = 2.0;  // m/s^2 at the rim
  int encoder_ticks_per_rev = 1024;
  double actuator_noise = 0.02;  // relative std-dev of each wheel's achieved speed
  double encoder_noise = 0.005;  // relative std-dev of each wheel's travel against the floor (slip)
  // Omnidirectional drive: wheel i sits at angle omni_wheel_angles[i] (rad, robot frame) at
  // omni_wheel_distance from the centre and rolls tangentially (Festo Robotino geometry).
  double omni_wheel_distance = 0.135;  // m
  std::vector<double> omni_wheel_angles = {0.0, 2.0 * M_PI / 3.0, 4.0 * M_PI / 3.0};
  // Unicycle (chapter 7): body-level limits on speed and on the acceleration inputs u1, u2.
  double max_speed = 1.5;          // m/s
  double max_angular_speed = 2.0;  // rad/s
  double max_accel = 1.0;          // m/s^2 (|u1|)
  double max_angular_accel = 4.0;  // rad/s^2 (|u2|)
};

// A laser range finder like the Hokuyo URG-04LX of seed 000.
struct LaserDescription {
  double fov = 240.0 * M_PI / 180.0;  // rad, centred on the robot's heading
  double range_min = 0.02;            // m
  double range_max = 4.0;             // m
  int beams = 683;
  double rate = 10.0;   // Hz
  double noise = 0.01;  // m, std-dev of range noise
  // m above the floor of the scanning plane: it sees only what crosses this height (a table's
  // legs, not its top; nothing of a box lower than it).
  double height = 0.2;
};

// An RGB-D camera like the Intel RealSense D435 on the robot, its depth as a point cloud. The
// mount is the camera's optical centre in the robot frame (x ahead, y left, z up from the floor)
// and its tilt down from level; the cloud is in the camera's optical frame (ROS REP 103: z along
// the optical axis, x right, y down), as ROS drivers publish it.
struct DepthCameraDescription {
  int width = 212, height = 120;        // pixels
  double hfov = 87.0 * M_PI / 180.0;    // rad, horizontal field of view
  double vfov = 58.0 * M_PI / 180.0;    // rad, vertical
  double range_min = 0.2;               // m along the optical axis (depth); nearer: no reading
  double range_max = 5.0;               // m
  double rate = 15.0;                   // Hz
  double mount_x = 0.1, mount_y = 0.0;  // m, robot frame
  double mount_z = 0.8;                 // m above the floor
  double tilt = 30.0 * M_PI / 180.0;    // rad down from level
  // Depth noise, a standard deviation that grows with the square of the depth (stereo depth's
  // error: sigma = noise * z^2, m with z in m), and the share of pixels with no reading (holes).
  double noise = 0.002;
  double holes = 0.02;
};

// An axis-aligned box in the map frame, metres.
struct Box {
  Point2 min = Point2::Zero();
  Point2 max = Point2::Zero();
  bool Contains(const Point2& p) const {
    return p.x() >= min.x() && p.y() >= min.y() && p.x() <= max.x() && p.y() <= max.y();
  }
};

// An area the robot drives through no faster than max_speed (Nav2's speed filter zones: loading
// bays, doorways, where people walk). Map frame, metres, m/s at the robot's rim.
struct SpeedZone {
  std::string name;
  Polygon area;  // a simple closed curve
  double max_speed = 0.0;
};

struct World {
  std::string name;
  std::string source;  // file path, or "<embedded>"
  OccupancyGrid map;
  Pose2 start;  // robot start pose in the map frame
  RobotDescription robot;
  LaserDescription laser;
  std::optional<DepthCameraDescription> camera;  // the robot carries one when set
  std::vector<Pose2> goals;                      // named demo goals, in order
  std::map<std::string, Box> regions;            // named areas (rooms, streets, spawn areas)
  std::vector<SpeedZone> speed_zones;
};

// Parses a world YAML. `base_dir` resolves a map file path given in it. Throws navd::Error naming
// the field on bad input.
World ParseWorld(const std::string& yaml_text, const std::string& source, const std::string& base_dir);
World LoadWorldFile(const std::string& path);
// The embedded default world (worlds/warehouse.yaml, compiled in).
World DefaultWorld();

// Loads a map file for a world: a map_server YAML or a MovingAI `.map` (by extension).
OccupancyGrid LoadMapFile(const std::string& path);

// Loads a world YAML (has a `map:` key), a map_server YAML (has `image:`) or a MovingAI `.map`
// (starts with `type`), as navd's --map and LoadMap accept. Returns the map and its name.
OccupancyGrid LoadAnyMapFile(const std::string& path, std::string* name = nullptr);
// The same three kinds as a world to simulate: a world file as it is; a bare map with the default
// robot and laser, started at the known-free spot nearest the map's centre where the robot fits
// with 5 cm to spare. Throws navd::Error(kInvalidArgument) naming the file when none fits.
World LoadWorldOrMapFile(const std::string& path);

}  // namespace navd
