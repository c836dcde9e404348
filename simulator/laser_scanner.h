#pragma once
// A planar laser range finder (default: Hokuyo URG-04LX): one ray per beam against the static
// world and every disc around (people, moving obstacles, other robots), Gaussian range noise,
// max-range readings reported as range_max + 1 so consumers can tell "no return". Angles in the
// robot frame, counter-clockwise; the scanner sits at the robot's centre.
#include <random>
#include <vector>

#include "services/common/world.h"
#include "services/common/ray_caster.h"
#include "services/common/disc.h"

namespace navd::sim {

class LaserScanner {
 public:
  explicit LaserScanner(const LaserDescription& description);
  // Ranges for a scanner at `pose` (map frame), beam i at angle angle_min() + i * increment().
  // Discs with id == `self` (the robot carrying the scanner) are not seen.
  std::vector<float> Scan(const Pose2& pose, const RayCaster& world, const std::vector<Disc>& discs, int self,
                          std::mt19937_64& rng) const;
  double angle_min() const { return -d_.fov / 2; }
  double angle_max() const { return d_.fov / 2; }
  double increment() const { return d_.beams > 1 ? d_.fov / (d_.beams - 1) : 0.0; }
  const LaserDescription& description() const { return d_; }

 private:
  LaserDescription d_;
  std::vector<Point2> beam_directions_;  // unit vectors in the scanner frame, so a scan needs no trigonometry per beam
};

}  // namespace navd::sim
