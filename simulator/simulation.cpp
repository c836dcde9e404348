#include "simulator/simulation.h"

#include <cmath>

namespace navd::sim {

Simulation::Simulation(World world, const SimulationOptions& options)
    : world_(std::move(world)),
      options_(options),
      rng_(options.seed),
      robot_(world_.robot, world_.start, rng_),
      laser_(world_.laser) {}

void Simulation::Command(const Twist2& twist) {
  if (!std::isfinite(twist.v) || !std::isfinite(twist.omega)) return;  // never act on NaN/inf
  robot_.Command(twist);
  last_command_ = now_;
  watchdog_stopped_ = false;
}

bool Simulation::Due(double rate, double& last) {
  const double period = 1.0 / rate;
  // A small tolerance keeps float steps from skipping a sample.
  if (now_ - last < period - 1e-9) return false;
  last = last < 0 ? now_ : last + period;
  if (now_ - last >= period) last = now_;  // fell behind: resynchronise, do not burst
  return true;
}

StepOutputs Simulation::Step() {
  if (!watchdog_stopped_ && now_ - last_command_ > options_.command_timeout) {
    robot_.Command({});
    watchdog_stopped_ = true;
  }
  robot_.Step(options_.physics_step, world_.map);
  now_ += options_.physics_step;

  StepOutputs out;
  if (Due(world_.laser.rate, last_scan_)) out.scan = laser_.Scan(robot_.true_pose(), world_.map, rng_);
  out.odom = Due(options_.odom_rate, last_odom_);
  out.truth = Due(options_.truth_rate, last_truth_);
  out.status = Due(options_.status_rate, last_status_);
  return out;
}

}  // namespace navd::sim
