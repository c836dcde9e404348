#pragma once
// The daemon's mapping runs, one at a time: starts and stops MappingSessions, passes the robot's
// scans on while a run is active, and keeps the last run's map readable after it stops.
// Thread-safe (gRPC handlers start and stop; the control loop submits).
#include <memory>
#include <mutex>

#include "services/mapping/mapping_session.h"

namespace navd::mapping {

class MapBuilder {
 public:
  // Throws navd::Error(kFailedPrecondition) while a run is active, and the session's errors.
  MappingStatus Start(const MappingSessionOptions& options, const Pose2& start);
  // Throws navd::Error(kFailedPrecondition) when no run is active.
  MappingStatus Stop();
  // Passed to the active run, if any.
  void Submit(const Pose2& odometry, const Pose2& localised, const RangeScan& scan);
  bool active() const;
  // The current or last run (nullptr before the first).
  std::shared_ptr<MappingSession> session() const;

 private:
  mutable std::mutex mutex_;
  std::shared_ptr<MappingSession> session_;
};

}  // namespace navd::mapping
