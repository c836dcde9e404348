#include "services/common/clock.h"

#include <chrono>
#include <thread>

namespace navd {
namespace {
double SteadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

SystemClock::SystemClock() : start_(SteadySeconds()) {}

double SystemClock::Now() const { return SteadySeconds() - start_; }

bool SystemClock::SleepUntil(double t, double max_wall_wait) {
  const double wait = std::min(t - Now(), max_wall_wait);
  if (wait > 0) std::this_thread::sleep_for(std::chrono::duration<double>(wait));
  return Now() >= t;
}

double SimClock::Now() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return now_;
}

bool SimClock::SleepUntil(double t, double max_wall_wait) {
  std::unique_lock<std::mutex> lock(mutex_);
  return cv_.wait_for(lock, std::chrono::duration<double>(max_wall_wait), [&] { return now_ >= t; });
}

void SimClock::Set(double t) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    // Samples arrive out of order now and then: older ones are dropped. A jump back by more than
    // a second is a restarted simulator, whose time is followed from there.
    if (t <= now_ && now_ - t < 1.0) return;
    now_ = t;
  }
  started_ = true;
  cv_.notify_all();
}

}  // namespace navd
