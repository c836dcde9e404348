#pragma once
// A simulation scenario: a world, the robots in it (drive, sensors, namespace), obstacles the
// robots' map does not show, scripted moving obstacles, pedestrians, target points and the random
// seed. `navsim --scenario FILE` runs one; see worlds/scenarios/ and the README for the format.
// Metres, radians, seconds, map frame.
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "services/common/world.h"
#include "simulator/crowd.h"
#include "simulator/moving_obstacle.h"
#include "simulator/range_sensor_array.h"

namespace navd::sim {

// A people detector, as a tracker on a real robot reports (people_msgs/People): every person within
// range_max and the field of view, seen through one another, with the velocity they walk with
// (book chapter 7's simulations: "the robot will only know the current position and velocity of
// each of the persons within a range of 45 m in front"). Gaussian noise on request.
struct PeopleSensorDescription {
  double range_max = 45.0;      // m, centre to centre
  double fov = 2.0 * M_PI;      // rad, centred on the heading
  double rate = 10.0;           // Hz
  double position_noise = 0.0;  // m, standard deviation per axis
  double velocity_noise = 0.0;  // m/s, standard deviation per axis
};

struct RobotSpec {
  std::string name;  // topic namespace (rt/<name>/scan ...); empty: rt/scan ...
  Pose2 start;
  RobotDescription body;
  std::optional<LaserDescription> laser;
  std::optional<RangeArrayDescription> sonar;
  std::optional<RangeArrayDescription> ir;
  std::optional<PeopleSensorDescription> people;
  std::optional<DepthCameraDescription> camera;
  bool bumper = false;
  bool encoders = false;
  double encoder_rate = 50.0;  // Hz
  double bumper_rate = 10.0;   // Hz
};

// A solid the robots' map does not show, with the height band it fills: a table top, a box lower
// than the laser's plane, a shelf that overhangs at head height. Map frame; metres above the floor.
struct Solid {
  Box box;
  double z_min = 0.0, z_max = 0.0;
};

struct Door {
  std::string name;
  Box box;
  bool closed = false;  // a closed door is a wall the robots' map does not show
};

struct Scenario {
  std::string name;
  std::string source;
  World world;                // what navd is given: map, default robot, goals, regions
  OccupancyGrid truth;        // what the sensors see: the map plus hidden obstacles and closed doors
  OccupancyGrid fixed_truth;  // the same with every door open, to rebuild `truth` when doors move
  std::vector<RobotSpec> robots;
  std::vector<MovingObstacleDescription> moving_obstacles;
  std::optional<CrowdDescription> crowd;
  std::vector<Door> doors;
  std::vector<Point2> targets;  // named target points, in visiting order (seed 000's 11)
  int hidden_obstacles = 0;     // how many obstacles are in `truth` but not in the map
  // Cells lasers see through: glass panes among the hidden obstacles (real glass doors and
  // partitions), and solids off the lasers' plane (a table's top, a low box). In `truth`: bumpers,
  // sonar and IR find them.
  std::vector<CellIndex> see_through;
  // The solids among the hidden obstacles, as depth cameras see them in 3-D; the cells only they
  // fill (`solid_cells`) are in `truth` where they are lower than the tallest robot, and free for
  // the depth camera's walls (walls and the other hidden obstacles stand floor to ceiling).
  std::vector<Solid> solids;
  std::vector<CellIndex> solid_cells;
  uint64_t seed = 1;
};

// `fixed` with the closed doors filled in.
OccupancyGrid TruthWithDoors(const OccupancyGrid& fixed, const std::vector<Door>& doors);

// `truth` with `cells` free: as a laser sees it (see_through), or the walls a depth camera sees
// beside the solids (solid_cells).
OccupancyGrid WithCellsFree(const OccupancyGrid& truth, const std::vector<CellIndex>& cells);

// One robot (no namespace) with the world's robot and laser, encoders and bumpers.
Scenario ScenarioFromWorld(World world);
// Throws navd::Error naming file, line and field on bad input.
Scenario ParseScenario(const std::string& yaml_text, const std::string& source, const std::string& base_dir);
Scenario LoadScenarioFile(const std::string& path);

}  // namespace navd::sim
