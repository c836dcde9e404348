#pragma once
// A mapping run inside navd: scans (with the odometry and the localiser's pose at the time) are
// handed over without blocking the caller, a worker thread builds the map, and readers take
// snapshots. Two modes: SLAM (GraphSlam from odometry and scans, its first node at the
// localiser's pose of the first scan; the map re-renders from the optimised poses after loop
// closures) and known poses (the localiser's pose, each scan straight
// into the grid). The map is a square of `size` metres centred on the robot's pose at the start,
// in navd's map frame; it tracks which cells changed so clients can fetch changed regions only.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "services/mapping/graph_slam.h"
#include "services/mapping/occupancy_grid_mapper.h"

namespace navd::mapping {

enum class MappingMode { kSlam, kKnownPoses };

struct MappingSessionOptions {
  MappingMode mode = MappingMode::kSlam;
  double resolution = 0.05;  // m
  double size = 60.0;        // m, the side of the square mapped
  // s between re-renders after the graph moved: of wall time, which bounds what re-rendering
  // costs a daemon however fast its scans come; of the scans' stamps when synchronous, so that a
  // run in one process maps the same on any machine and at any load.
  double rerender_period = 2.0;
  // Submit integrates in the caller's thread and nothing is dropped (offline tools, simulations
  // in one process); otherwise a worker thread does, in order.
  bool synchronous = false;
  // Scans the worker may fall behind by: SLAM takes a few milliseconds per scan but ten times that
  // now and then (a loop closure's optimisation, a front-end recovery's wider search), and a scan
  // it drops leaves a gap the next scan's odometry must bridge. Beyond this, the oldest waiting
  // scan is dropped.
  int max_waiting = 10;
  // A robot's odometry errs beyond the SLAM front end's window at times (wheels slipping, a
  // sharp turn between two scans), so the front end searches poorly matched scans again wider;
  // and it errs the same way step after step (a wheel radius off), which SLAM learns and takes out.
  GraphSlamOptions slam = [] {
    GraphSlamOptions s;
    s.front_recovery = RobotOdometryRecovery();
    s.odometry_bias = RobotOdometryBias();
    return s;
  }();
  MapperOptions mapper;
};

// A changed region: cells [min, max] (inclusive) of the session's grid.
struct MapRegion {
  CellIndex min, max;
};

struct MappingStatus {
  bool active = false;
  MappingMode mode = MappingMode::kSlam;
  uint64_t scans = 0;  // scans integrated (the worker drops scans it cannot keep up with)
  uint64_t dropped = 0;
  int nodes = 0, loop_closures = 0;
  Pose2 pose;            // the robot's latest mapped pose, map frame
  double stamp = 0.0;    // s, the stamp of the scan `pose` belongs to
  uint64_t version = 0;  // increments with every change of the map
};

class MappingSession {
 public:
  // Throws navd::Error(kInvalidArgument) for a bad resolution, size (refused before allocating) or
  // max_waiting.
  MappingSession(const MappingSessionOptions& options, const Pose2& start);
  ~MappingSession();
  MappingSession(const MappingSession&) = delete;
  MappingSession& operator=(const MappingSession&) = delete;

  // Hands a scan to the worker (queued behind up to max_waiting others).
  void Submit(const Pose2& odometry, const Pose2& localised, const RangeScan& scan);
  // Stops taking scans, waits for the worker to finish the scans handed over, refines a SLAM run
  // (GraphSlam::Refine: about a loop closure's match per node, a second or two for a building's
  // few hundred nodes) and draws the map again. The map stays readable meanwhile.
  void Finish();

  MappingStatus status() const;
  // The map as it stands (occupancy 0..100, -1 unknown).
  std::shared_ptr<const OccupancyGrid> Map() const;
  // The region changed since `version`, or nullopt when nothing changed; the whole map when the
  // changes are too old to tell apart. `covers`: the version the region brings a reader up to.
  std::optional<MapRegion> ChangedSince(uint64_t version, uint64_t* covers = nullptr) const;

 private:
  struct Item {
    Pose2 odometry, localised;
    RangeScan scan;
  };
  void Work();
  void Integrate(const Item& item);
  void Render();  // the whole map again from the optimised nodes (SLAM)
  // The clock rerender_period counts in (s): the wall's, or a synchronous run's scan stamp.
  double RenderClock(double stamp) const;
  void MarkChanged(const MapRegion& region);

  MappingSessionOptions o_;
  OccupancyGrid geometry_;                       // the grid's size, origin and resolution (fixed)
  std::unique_ptr<OccupancyGridMapper> mapper_;  // replaced by the worker (under mapper_mutex_)
  std::unique_ptr<GraphSlam> slam_;              // worker only
  int rendered_optimisations_ = 0;               // the graph's, when the map was last drawn from it
  double last_render_ = -1e9;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Item> waiting_;
  bool finishing_ = false;
  std::mutex finish_mutex_;  // one Finish at a time
  MappingStatus status_;
  mutable std::shared_ptr<const OccupancyGrid> snapshot_;  // rebuilt on demand when stale
  mutable uint64_t snapshot_version_ = 0;
  std::deque<std::pair<uint64_t, MapRegion>> changes_;  // recent changes, oldest first
  mutable std::mutex mapper_mutex_;                     // the worker writes, Map() reads
  std::thread worker_;
};

}  // namespace navd::mapping
