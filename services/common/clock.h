#pragma once
// Time source for control loops. Seconds as double; SystemClock counts from process start,
// SimClock follows the simulator's rt/clock so runs faster than real time stay consistent.
#include <atomic>
#include <condition_variable>
#include <mutex>

namespace navd {

class Clock {
 public:
  virtual ~Clock() = default;
  // Current time in seconds.
  virtual double Now() const = 0;
  // Blocks until Now() >= t, or until `max_wall_wait` wall seconds pass (so callers stay
  // responsive when simulated time stops). Returns true when t was reached.
  virtual bool SleepUntil(double t, double max_wall_wait) = 0;
};

class SystemClock : public Clock {
 public:
  SystemClock();
  double Now() const override;
  bool SleepUntil(double t, double max_wall_wait) override;

 private:
  double start_;
};

class SimClock : public Clock {
 public:
  double Now() const override;
  bool SleepUntil(double t, double max_wall_wait) override;
  // Fed from rt/clock. Slightly older stamps (reordering) are ignored; a jump back of more than
  // a second (a restarted simulator) resets the clock.
  void Set(double t);
  // True once a clock message has arrived.
  bool started() const { return started_.load(); }

 private:
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  double now_ = 0.0;
  std::atomic<bool> started_{false};
};

}  // namespace navd
