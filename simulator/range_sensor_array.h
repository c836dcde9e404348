#pragma once
// A ring of cone-shaped range sensors: the sonar ring of a Pioneer (seeds 002 and 004) or the
// Sharp IR proximity sensors of seed 000. Each sensor sits on the robot's rim, looks outward along
// its mounting angle, and reports the nearest echo inside its cone (sampled by a few rays), with
// Gaussian noise; no echo reads range_max. Angles in the robot frame (radians, counter-clockwise);
// metres.
#include <random>
#include <string>
#include <vector>

#include "services/common/ray_caster.h"
#include "services/common/disc.h"

namespace navd::sim {

struct RangeArrayDescription {
  std::string kind;            // "sonar" or "ir": names the topic and the ROS radiation type
  std::vector<double> angles;  // rad, robot frame
  double mount_radius = 0.20;  // m from the robot's centre
  double cone = 0.0;           // rad, full opening angle (0: a single ray)
  int rays_per_cone = 1;
  double range_min = 0.0;  // m
  double range_max = 1.0;  // m
  double noise = 0.0;      // m, std-dev
  double rate = 10.0;      // Hz, the whole array
};

// Pioneer 2/3 sonar ring: 16 Polaroid transducers (8 front, 8 rear), 0.1-5 m, 15 degree cones.
RangeArrayDescription PioneerSonarRing(double robot_radius);
// Seed 000: two Sharp GP2D12 IR sensors at +-30 degrees in front, one straight back (0.1-0.8 m).
RangeArrayDescription Gp2d12Triple(double robot_radius);

class RangeSensorArray {
 public:
  explicit RangeSensorArray(RangeArrayDescription description) : d_(std::move(description)) {}
  std::vector<float> Read(const Pose2& pose, const RayCaster& world, const std::vector<Disc>& discs, int self,
                          std::mt19937_64& rng) const;
  const RangeArrayDescription& description() const { return d_; }

 private:
  RangeArrayDescription d_;
};

}  // namespace navd::sim
