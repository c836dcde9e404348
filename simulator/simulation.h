#pragma once
// One simulated world stepped in fixed increments of simulated time: the robot's physics every
// step, sensors only at their physical rates (seed 000: "only with the frequency allowed by the
// physical counterpart"), and the command watchdog. No transport: navsim_main.cpp moves data to
// and from DDS. Seconds of simulated time; map frame.
#include <functional>
#include <optional>
#include <random>
#include <vector>

#include "services/common/world.h"
#include "simulator/diff_drive_robot.h"
#include "simulator/laser_scanner.h"

namespace navd::sim {

struct SimulationOptions {
  double physics_step = 0.01;       // s
  double odom_rate = 50.0;          // Hz (encoders are read at this rate)
  double truth_rate = 50.0;         // Hz
  double status_rate = 10.0;        // Hz
  double command_timeout = 0.5;     // s without a command stops the robot
  uint64_t seed = 1;
};

// What became due during one step.
struct StepOutputs {
  std::optional<std::vector<float>> scan;
  bool odom = false;
  bool truth = false;
  bool status = false;
};

class Simulation {
 public:
  Simulation(World world, const SimulationOptions& options);

  // A velocity command arriving now (simulated time).
  void Command(const Twist2& twist);
  StepOutputs Step();

  double now() const { return now_; }
  const DiffDriveRobot& robot() const { return robot_; }
  const LaserScanner& laser() const { return laser_; }
  const World& world() const { return world_; }
  const SimulationOptions& options() const { return options_; }
  bool watchdog_stopped() const { return watchdog_stopped_; }

 private:
  // True when the period of a `rate` Hz stream has elapsed since `last`; advances `last`.
  bool Due(double rate, double& last);

  World world_;
  SimulationOptions options_;
  std::mt19937_64 rng_;
  DiffDriveRobot robot_;
  LaserScanner laser_;
  double now_ = 0.0;
  double last_command_ = -1e9;
  bool watchdog_stopped_ = true;
  double last_scan_ = -1e9, last_odom_ = -1e9, last_truth_ = -1e9, last_status_ = -1e9;
};

}  // namespace navd::sim
