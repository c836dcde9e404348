#pragma once
// One simulated world stepped in fixed increments of simulated time: every robot's physics, the
// scripted obstacles and the people every step; each sensor only at its physical rate (seed 000:
// "only with the frequency allowed by the physical counterpart"); command watchdogs; contacts.
// Deterministic: the same scenario, seed and command sequence give bit-identical runs. No
// transport: navsim's RobotTopics and WorldTopics move data to and from DDS. Seconds of simulated time; map frame.
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "simulator/crowd.h"
#include "simulator/depth_camera.h"
#include "simulator/laser_scanner.h"
#include "simulator/mobile_base.h"
#include "simulator/moving_obstacle.h"
#include "simulator/range_sensor_array.h"
#include "services/common/ray_caster.h"
#include "services/common/disc.h"
#include "simulator/scenario.h"

namespace navd::sim {

struct SimulationOptions {
  double physics_step = 0.01;    // s
  double odom_rate = 50.0;       // Hz
  double truth_rate = 50.0;      // Hz
  double status_rate = 10.0;     // Hz
  double command_timeout = 0.5;  // s without a command stops the robot
  // Overrides the scenario's seed when set (navsim --seed).
  std::optional<uint64_t> seed;
};

// A robot's collision: its own motion ran it into something; reported once when the contact begins.
struct CollisionEvent {
  double time = 0.0;
  std::string robot;
  std::string other;     // "wall", a robot's or obstacle's name, or "person <id>"
  int other_id = kWall;  // the body's id (Crowd::kFirstPersonId and up: a person), or kWall
  Point2 where = Point2::Zero();
  // Who closed the gap (m/s, along the line between the two centres): the robot's speed towards
  // the other (towards a wall, its speed), and the other's towards the robot (a person's walking
  // speed, a robot's or an obstacle's; 0 for a wall). A robot driving on as someone walks into its
  // side touches them with a small robot_closing and a large other_closing.
  double robot_closing = 0.0;
  double other_closing = 0.0;
};

struct BumperState {
  bool front = false;
  bool rear = false;
};

class SimulatedRobot {
 public:
  SimulatedRobot(const RobotSpec& spec, int id, uint64_t seed);
  const RobotSpec& spec() const { return spec_; }
  const std::string& name() const { return spec_.name; }
  int id() const { return id_; }
  MobileBase& base() { return base_; }
  const MobileBase& base() const { return base_; }
  const std::optional<LaserScanner>& laser() const { return laser_; }
  const std::optional<RangeSensorArray>& sonar() const { return sonar_; }
  const std::optional<RangeSensorArray>& ir() const { return ir_; }
  const std::optional<DepthCamera>& camera() const { return camera_; }
  uint32_t collisions() const { return collisions_; }
  bool in_collision() const { return in_contact_; }
  const BumperState& bumper() const { return bumper_; }
  bool watchdog_stopped() const { return watchdog_stopped_; }

 private:
  friend class Simulation;
  RobotSpec spec_;
  int id_;
  std::mt19937_64 sensor_rng_;
  std::mt19937_64 people_rng_;  // the people sensor's noise, apart: turning it on leaves the others' draws
  std::mt19937_64 camera_rng_;  // the depth camera's holes and noise, apart likewise
  MobileBase base_;
  std::optional<LaserScanner> laser_;
  std::optional<RangeSensorArray> sonar_, ir_;
  std::optional<DepthCamera> camera_;
  bool camera_watched_ = true;
  double last_command_ = -1e9;
  bool watchdog_stopped_ = true;
  bool in_contact_ = false;  // touching something now
  double last_contact_ = -1e9;
  bool contact_this_step_ = false;
  std::string contact_with_;
  int contact_other_id_ = kWall;
  Point2 contact_where_ = Point2::Zero();
  double contact_robot_closing_ = 0.0, contact_other_closing_ = 0.0;
  BumperState bumper_;
  uint32_t collisions_ = 0;
  double last_scan_ = -1e9, last_sonar_ = -1e9, last_ir_ = -1e9, last_odom_ = -1e9, last_encoders_ = -1e9,
         last_bumper_ = -1e9, last_people_ = -1e9, last_camera_ = -1e9;
};

// A person the people sensor reports: robot frame (metres), velocity over the ground in the robot
// frame's axes (m/s, the velocity they walk with).
struct PersonReading {
  int id = 0;
  Point2 position = Point2::Zero();
  Point2 velocity = Point2::Zero();
};

// What became due for one robot during one step.
struct RobotReadings {
  std::optional<std::vector<float>> scan;
  std::optional<std::vector<float>> sonar;
  std::optional<std::vector<float>> ir;
  std::optional<std::vector<PersonReading>> people;
  // The depth camera's points, its optical frame (DepthCamera::Capture).
  std::optional<std::vector<Eigen::Vector3f>> camera;
  bool odom = false;
  bool encoders = false;
  bool bumper = false;
};

struct StepOutputs {
  std::vector<RobotReadings> robots;  // indexed like Simulation::robots()
  bool truth = false;                 // ground truth of robots, obstacles and people
  bool status = false;
  std::vector<CollisionEvent> events;
};

class Simulation {
 public:
  Simulation(Scenario scenario, const SimulationOptions& options);
  // The single-robot form: a world file's robot, laser, encoders and bumpers.
  Simulation(World world, const SimulationOptions& options);

  // Commands for robot `index` arriving now (simulated time). Non-finite values are ignored.
  void Command(size_t index, const BodyTwist& twist);
  void CommandAcceleration(size_t index, double linear, double angular);
  // Whether anyone takes robot `index`'s depth images: an image nobody takes is not rendered (it
  // changes nothing else: the camera draws from a random stream of its own). On by default.
  void SetCameraWatched(size_t index, bool watched);
  StepOutputs Step();
  // Opens or closes the scenario's door `name` now; the sensors see it from the next reading.
  // Throws navd::Error: kNotFound (listing the doors) for an unknown name, kFailedPrecondition
  // when closing it would shut it on a robot, an obstacle or a person.
  void SetDoor(const std::string& name, bool closed);

  double now() const { return now_; }
  const std::vector<std::unique_ptr<SimulatedRobot>>& robots() const { return robots_; }
  const SimulatedRobot& robot(size_t index = 0) const { return *robots_.at(index); }
  const std::vector<MovingObstacle>& moving_obstacles() const { return obstacles_; }
  const std::vector<Person>& people() const;
  const Crowd* crowd() const { return crowd_.get(); }
  const Scenario& scenario() const { return scenario_; }
  const World& world() const { return scenario_.world; }
  const RayCaster& truth() const { return truth_; }
  // What lasers see: the truth without what they see through.
  const RayCaster& laser_truth() const { return laser_truth_ ? *laser_truth_ : truth_; }
  // What depth cameras see as walls (floor to ceiling): the truth without the solids.
  const RayCaster& camera_walls() const { return camera_walls_ ? *camera_walls_ : truth_; }
  const SimulationOptions& options() const { return options_; }
  uint64_t seed() const { return seed_; }
  // Every body as a disc: robots, moving obstacles, people (current positions).
  std::vector<Disc> Discs() const;
  // Name of body `id` for events and truth messages.
  std::string BodyName(int id) const;

 private:
  // laser_truth_ and camera_walls_ from the truth as it is now.
  void RebuildViews();
  // Step's parts, in its order: the robots (each against the others where they are now, stopped
  // by its watchdog), the scripted obstacles, then, after the crowd and the clock, the contacts
  // counted as collisions and the sensors due.
  void MoveRobots(double dt);
  void MoveObstacles(double dt);
  std::vector<CollisionEvent> CountCollisions();
  std::vector<RobotReadings> ReadSensors();
  // True when the period of a `rate` Hz stream has elapsed since `last`; advances `last`.
  bool Due(double rate, double& last) const;
  // kFree, kWall or the body id a disc at `centre` would overlap (ignoring `self`).
  int Occupied(const Point2& centre, double radius, int self, bool robots_only) const;
  // robot_moved: the robot's own motion touched `other`, closing at these speeds (CollisionEvent's).
  void Touch(SimulatedRobot& robot, int other, const Point2& where, bool robot_moved, double robot_closing = 0.0,
             double other_closing = 0.0);
  // Where body `id` (not a wall) is and how fast it goes (map frame, m/s; a person's walking
  // velocity); nullopt for an id that is no body.
  std::optional<std::pair<Point2, Point2>> BodyMotion(int id) const;
  // What robot `r`'s people sensor reports now.
  std::vector<PersonReading> SensePeople(SimulatedRobot& r);

  Scenario scenario_;
  SimulationOptions options_;
  uint64_t seed_;
  RayCaster truth_;
  std::optional<RayCaster> laser_truth_;   // only when lasers see through something
  std::optional<RayCaster> camera_walls_;  // only with solids: the truth without them
  std::vector<std::unique_ptr<SimulatedRobot>> robots_;
  std::vector<MovingObstacle> obstacles_;
  std::unique_ptr<Crowd> crowd_;
  double now_ = 0.0;
  double last_truth_ = -1e9, last_status_ = -1e9;
};

}  // namespace navd::sim
