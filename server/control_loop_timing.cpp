#include "server/control_loop_timing.h"

#include <spdlog/fmt/fmt.h>

#include <algorithm>

#include "services/common/quantile.h"

namespace navd::server {
namespace {

float Milliseconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<float, std::milli>(d).count();
}

}  // namespace

void ControlLoopTiming::Add(std::vector<float>& samples, size_t& next, size_t capacity, float value) {
  if (samples.size() < capacity) {
    samples.push_back(value);
  } else {
    samples[next] = value;
    next = (next + 1) % capacity;
  }
}

void ControlLoopTiming::TickStarted(Time now) {
  if (ticked_) Add(periods_ms_, next_period_, capacity_, Milliseconds(now - last_tick_));
  ticked_ = true;
  last_tick_ = now;
  ++ticks_;
}

void ControlLoopTiming::CommandAfterScan(Time scan_arrival, Time tick_start, Time now) {
  Add(latencies_ms_, next_latency_, capacity_, Milliseconds(now - scan_arrival));
  Add(work_ms_, next_work_, capacity_, Milliseconds(now - tick_start));
}

std::string ControlLoopTiming::Summary() const {
  return fmt::format(
      "{} ticks, period median {:.2f} ms (p95 {:.2f}, max {:.2f}); scan to cmd_vel median {:.2f} ms (p95 {:.2f}), "
      "of which work median {:.3f} ms (p95 {:.3f}), over {} scans",
      ticks_, Quantile(periods_ms_, 0.5), Quantile(periods_ms_, 0.95), Quantile(periods_ms_, 1.0),
      Quantile(latencies_ms_, 0.5), Quantile(latencies_ms_, 0.95), Quantile(work_ms_, 0.5), Quantile(work_ms_, 0.95),
      latencies_ms_.size());
}

}  // namespace navd::server
