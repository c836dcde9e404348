#include "simulator/step_pacer.h"

#include <thread>

namespace navd::sim {

StepPacer::StepPacer(const StepPacerOptions& options)
    : options_(options), start_(std::chrono::steady_clock::now()), schedule_start_(start_) {}

void StepPacer::AfterStep() {
  ++scheduled_steps_;
  if (options_.fast) return;
  const auto now = std::chrono::steady_clock::now();
  const double ahead = static_cast<double>(scheduled_steps_) * options_.step / options_.rate -
                       std::chrono::duration<double>(now - schedule_start_).count();
  if (ahead > 0) {
    std::this_thread::sleep_for(std::chrono::duration<double>(ahead));
  } else if (options_.restart_behind >= 0.0 && ahead < -options_.restart_behind) {
    schedule_start_ = now;
    scheduled_steps_ = 0;
  }
}

double StepPacer::WallSeconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

}  // namespace navd::sim
