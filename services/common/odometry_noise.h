#pragma once
// The documented, seeded noise model that turns a log's corrected poses into odometry for replays
// (navd-replay offline, navctl replay over DDS): per step between consecutive poses, the
// translation is scaled by (1 + S)(1 + N(0, T)), and the heading change gains D x distance plus
// N(0, R x distance) plus N(0, T x |turn|). Default T = 0.05 (5 %), R = 0.035 rad/m (2 degrees per
// metre), and no systematic error (S = D = 0): the evaluation protocol's error averages out, a
// robot's own (a wheel radius off, wheels of unequal radius) does not. The odometry starts at its
// own frame's origin. Metres, radians.
#include <cstdint>
#include <random>
#include <string>

#include "services/common/pose2.h"

namespace navd {

struct OdometryNoise {
  double translation = 0.05;          // T: relative std-dev of each step's translation
  double rotation_per_metre = 0.035;  // R: rad of heading std-dev per metre driven
  double scale_error = 0.0;           // S: every step's translation scaled by 1 + S
  double drift = 0.0;                 // D: rad of heading every metre driven adds
};

// Parses "T,R" (both >= 0) or "T,R,S,D" (S > -1, D finite); throws std::invalid_argument naming
// `option` and the text otherwise.
OdometryNoise ParseOdometryNoise(const std::string& text, const std::string& option = "--odom-noise");

class OdometryCorruptor {
 public:
  OdometryCorruptor(const OdometryNoise& noise, uint64_t seed) : noise_(noise), rng_(seed) {}
  // The odometry pose for the next true pose (the first call returns the origin).
  Pose2 Next(const Pose2& truth);

 private:
  OdometryNoise noise_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  bool started_ = false;
  Pose2 last_truth_;
  Pose2 odometry_;
};

}  // namespace navd
