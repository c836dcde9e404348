#pragma once
// The wake-up's whole-map search, run beside the estimate on a localiser of its own that is fed
// the same odometry and scans. A scan on the search's 100 000 particles takes a good part of a
// second on one core: on its own thread (`asynchronous`) the search weighs the newest scan when it
// is free, dropping those that came meanwhile, and moves through every odometry reading up to that
// scan's stamp, so the caller (navd's control loop) never waits for it. Synchronous, each scan is
// weighed in AddScan, as offline replays and tests want (deterministic).
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "services/localization/localizer.h"

namespace navd::localization {

class BesideSearch {
 public:
  // `localizer` has been scattered over the map (GlobalRelocalize).
  BesideSearch(std::unique_ptr<Localizer> localizer, bool asynchronous);
  // Does not wait for a scan being weighed: the worker finishes it and ends on its own.
  ~BesideSearch();
  BesideSearch(const BesideSearch&) = delete;
  BesideSearch& operator=(const BesideSearch&) = delete;

  void AddOdometry(const OdometryReading& reading);
  void AddScan(const ScanReading& scan);
  void SetMap(const OccupancyGrid& map);
  // What the search made of the last scan it used, stamped with that scan (a caller counts scans,
  // not calls); before its first scan, the scattered cloud.
  PoseEstimate Estimate() const;
  // Scans weighed so far (for tests and logs).
  uint64_t scans_used() const;

 private:
  struct State;
  static void Run(const std::shared_ptr<State>& state);
  // Weighs one scan with the search's localiser (the caller's thread or the worker's, whichever
  // owns it) and keeps what it made of it, stamped with the scan.
  static void Weigh(State& state, const ScanReading& scan);
  std::shared_ptr<State> state_;
  bool asynchronous_;
};

}  // namespace navd::localization
