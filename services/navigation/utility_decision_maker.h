#pragma once
// Utility-function (UF) decision making, Wahde et al. (seed 000, section 3). Every brain process i
// has a utility u_i in [-1, 1] that follows
//     tau_i du_i/dt + u_i = tanh(c_i (sum_k a_ik z_k + b_i + Gamma_i))
// over the state variables z_k (what the robot measures: danger, contact, lost, ...). Exactly one
// motor behaviour runs at a time, the one with the highest utility; every cognitive process with
// positive utility runs. A process may set its own gamma Gamma_i, which then decays exponentially
// with time constant tau_i^Gamma; the seed's avoidance sets it on activation so that it is not
// switched off the moment it has turned away from the danger.
#include <cstddef>
#include <string>
#include <vector>

namespace navd::navigation {

enum class ProcessKind { kMotor, kCognitive };

struct UtilityProcessOptions {
  std::string name;
  ProcessKind kind = ProcessKind::kMotor;
  double tau = 0.1;                               // s, reaction time
  double c = 1.0;                                 // steepness of tanh
  double b = 0.0;                                 // bias
  std::vector<std::pair<std::string, double>> a;  // weights a_ik by state-variable name
  double gamma_tau = 1.0;                         // s, decay time constant of Gamma_i
  // Gamma_i is set to this when the process becomes active (0: the process never sets it).
  double gamma_on_activation = 0.0;
};

struct UtilityBrainOptions {
  std::vector<std::string> state_variables;
  std::vector<UtilityProcessOptions> processes;
  // u_i at start-up; the seed does not say, so processes start neutral.
  double initial_utility = 0.0;
};

// One process's standing, for telemetry: why the robot does what it does.
struct ProcessUtility {
  std::string name;
  ProcessKind kind = ProcessKind::kMotor;
  double utility = 0.0;
  double gamma = 0.0;
  bool active = false;
};

class UtilityDecisionMaker {
 public:
  // Throws navd::Error(kInvalidArgument) naming the process and field: no motor behaviour,
  // duplicate names, a weight on an unknown state variable, non-positive time constants.
  explicit UtilityDecisionMaker(UtilityBrainOptions options);

  // Advances the utilities by dt seconds with the state variables z (ordered as
  // options.state_variables; the most recent value of each, held), then re-decides which processes
  // are active. Integrates exactly for constant inputs over the step, so any dt is stable.
  void Update(double dt, const std::vector<double>& z);
  // A process setting its own gamma (e.g. to a large negative value when it has run its course).
  void SetGamma(size_t process, double gamma);

  size_t active_motor() const { return active_motor_; }
  bool active(size_t process) const { return active_[process]; }
  // True when `process` turned active at the last Update.
  bool activated(size_t process) const { return active_[process] && !was_active_[process]; }
  double utility(size_t process) const { return utility_[process]; }
  size_t size() const { return options_.processes.size(); }
  const std::string& name(size_t process) const { return options_.processes[process].name; }
  // Index of a process or state variable by name; throws navd::Error(kInvalidArgument).
  size_t ProcessIndex(const std::string& name) const;
  size_t StateIndex(const std::string& name) const;
  // -1 when there is no such process (optional processes a configuration may leave out).
  long FindProcess(const std::string& name) const;
  std::vector<ProcessUtility> Snapshot() const;
  const UtilityBrainOptions& options() const { return options_; }

 private:
  void Decide();

  UtilityBrainOptions options_;
  std::vector<std::vector<std::pair<size_t, double>>> weights_;  // per process: (state index, a_ik)
  std::vector<double> utility_, gamma_;
  std::vector<bool> active_, was_active_;
  size_t active_motor_ = 0;
};

// The delivery robot's brain of seed 000 section 6 (grid navigation b = 0.25, tau = 0.1 s, c = 1),
// with the emergency stop and wake-up processes the seed proposes in section 7, and laser
// localisation as an always-on cognitive process. The same as config/brain.yaml.
UtilityBrainOptions DefaultBrainOptions();

// Reads a brain file (the format of config/brain.yaml). Throws navd::Error(kInvalidArgument) with
// the file, line and field.
UtilityBrainOptions LoadBrainFile(const std::string& path);
UtilityBrainOptions ParseBrain(const std::string& text, const std::string& source);

}  // namespace navd::navigation
