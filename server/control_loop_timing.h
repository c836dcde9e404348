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
  // A command went out at `now` in the tick that consumed a scan which arrived at `scan_arrival`.
  void CommandAfterScan(Time scan_arrival, Time now);
  // "N ticks, period median ... ms (p95 ..., max ...); scan to cmd_vel median ... ms (p95 ...) over M scans"
  std::string Summary() const;

 private:
  static void Add(std::vector<float>& samples, size_t& next, size_t capacity, float value);
  size_t capacity_;
  Time last_tick_{};
  bool ticked_ = false;
  size_t ticks_ = 0;
  std::vector<float> periods_ms_, latencies_ms_;
  size_t next_period_ = 0, next_latency_ = 0;
};

}  // namespace navd::server
