#pragma once
// What the robot's own sensors show round it that the map may lack, for the motor behaviours, the
// command guards and the plans: the last scan's returns, the 3-D obstacle layer's cells, and
// what only the sonar or a bumper found (discs, remembered a while). Written by the control
// thread, read by gRPC threads too: thread-safe. Map frame unless said.
#include <memory>
#include <mutex>
#include <vector>

#include "services/common/pose2.h"

namespace navd::navigation {

class SensedObstacles {
 public:
  struct Disc {
    Point2 position;
    double radius = 0.0;   // m
    double seen_at = 0.0;  // s
  };

  void SetScanReturns(std::vector<Point2> returns);
  bool has_scan_returns() const;
  void SetLayerCells(std::shared_ptr<const std::vector<Point2>> cells);
  std::shared_ptr<const std::vector<Point2>> layer_cells() const;
  // The scan's returns in the frame of a robot at `pose`, and the layer's cells within 2 m of it
  // (farther ones cannot bind a guard: the robot stops from full speed well within that).
  std::vector<Point2> LocalPoints(const Pose2& pose) const;

  // Keeps a disc of `radius` at `at` seen at `now`; a nearer look at a place replaces a wider one.
  void Remember(const Point2& at, double radius, double now);
  // Forgets the discs not seen for more than `memory` seconds before `now`; all with ForgetAll.
  void Forget(double now, double memory);
  void ForgetAll();
  std::vector<Disc> discs() const;

 private:
  mutable std::mutex mutex_;
  std::vector<Point2> returns_;
  std::shared_ptr<const std::vector<Point2>> cells_;
  std::vector<Disc> discs_;
};

}  // namespace navd::navigation
