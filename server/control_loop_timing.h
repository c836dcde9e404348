#pragma once
// How steadily the control loop runs, in wall time: the period between tick starts and the
// latency from a scan's arrival to the velocity command of the tick that used it. navd logs the
// summary when it stops; the live view's benchmark (scripts/view-bench) compares it with and
// without viewers. Control thread only; keeps the newest samples, so memory stays bounded.
#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

namespace navd::server {

class ControlLoopTiming {
 public:
  using Time = std::chrono::steady_clock::time_point;
  explicit ControlLoopTiming(size_t capacity = 100000) : capacity_(capacity) {}
  void TickStarted(Time now);
  // A command went out at `now` in the tick that started at `tick_start` and consumed a scan
  // which arrived at `scan_arrival`. The latency is the wait for the tick (set by the phase between
  // the laser's clock and the loop's, which drifts from run to run) plus the tick's work up to the
  // command (what load on the machine stretches); both are kept.
  void CommandAfterScan(Time scan_arrival, Time tick_start, Time now);
  // "N ticks, period median ... ms (p95 ..., max ...); scan to cmd_vel median ... ms (p95 ...), of
  // which work median ... ms (p95 ...), over M scans"
  std::string Summary() const;

 private:
  static void Add(std::vector<float>& samples, size_t& next, size_t capacity, float value);
  size_t capacity_;
  Time last_tick_{};
  bool ticked_ = false;
  size_t ticks_ = 0;
  std::vector<float> periods_ms_, latencies_ms_, work_ms_;
  size_t next_period_ = 0, next_latency_ = 0, next_work_ = 0;
};

}  // namespace navd::server
