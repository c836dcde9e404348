#include "simulator/lockstep_gate.h"

#include <algorithm>

namespace navd::sim {

namespace {
// Clock stamps and tick times are sums of doubles: a tick "at" t counts as reached.
constexpr double kEpsilon = 1e-9;
}  // namespace

LockstepGate::LockstepGate(size_t robots, double timeout) : timeout_(timeout), controllers_(robots) {}

void LockstepGate::Report(size_t robot, double next_tick) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (robot >= controllers_.size()) return;
    controllers_[robot].held = true;
    controllers_[robot].next_tick = next_tick;
  }
  cv_.notify_all();
}

bool LockstepGate::AllowedLocked(double t) const {
  for (const Controller& c : controllers_)
    if (c.held && t >= c.next_tick - kEpsilon) return false;
  return true;
}

std::vector<size_t> LockstepGate::WaitUntilAllowed(double t, const std::function<void()>& while_held) {
  using Clock = std::chrono::steady_clock;
  const auto deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_));
  const auto repeat = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kRepeatPeriod));
  std::unique_lock<std::mutex> lock(mutex_);
  std::vector<size_t> released;
  while (!AllowedLocked(t)) {
    const auto now = Clock::now();
    if (now >= deadline) {
      for (size_t i = 0; i < controllers_.size(); ++i) {
        if (controllers_[i].held && t >= controllers_[i].next_tick - kEpsilon) {
          controllers_[i].held = false;
          released.push_back(i);
        }
      }
      break;
    }
    if (cv_.wait_until(lock, while_held ? std::min(deadline, now + repeat) : deadline,
                       [&] { return AllowedLocked(t); }))
      break;
    if (while_held && Clock::now() < deadline) {
      lock.unlock();
      while_held();
      lock.lock();
    }
  }
  return released;
}

bool LockstepGate::holding() const {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const Controller& c : controllers_)
    if (c.held) return true;
  return false;
}

}  // namespace navd::sim
