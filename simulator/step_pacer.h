#pragma once
// Paces a simulation loop to `rate` simulated seconds per wall second: after each step it sleeps
// only while ahead of schedule, so that a long run keeps to its rate though single steps vary.
#include <chrono>
#include <cstdint>

namespace navd::sim {

struct StepPacerOptions {
  double step = 0.01;  // simulated seconds per step
  double rate = 1.0;   // simulated seconds per wall second
  bool fast = false;   // no pacing: as fast as the machine steps
  // Under lockstep a slow controller holds the simulation back: once the schedule is this many wall
  // seconds behind, it starts again from now instead of racing to catch up with the wall clock.
  // Negative: never (a paced run catches up after a slow stretch).
  double restart_behind = -1.0;
};

class StepPacer {
 public:
  explicit StepPacer(const StepPacerOptions& options);
  // After each step: sleeps while the run is ahead of its schedule.
  void AfterStep();
  // Wall seconds since the pacer was made.
  double WallSeconds() const;

 private:
  StepPacerOptions options_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point schedule_start_;
  uint64_t scheduled_steps_ = 0;
};

}  // namespace navd::sim
