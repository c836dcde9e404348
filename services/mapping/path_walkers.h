#pragma once
// People walking a log's own path, so that a log rendered again (log_renderer.h) has passers-by in
// it as real logs do: each walks along the path's length at a pace of their own, back and forth
// between its ends, a little to one side of it. Where the robot drove is free, so they walk only
// where people can, and along the corridors the robot itself drives, towards it and ahead of it.
// Metres, seconds, the log's frame.
#include <cstdint>
#include <vector>

#include "services/common/disc.h"
#include "services/common/pose2.h"

namespace navd::mapping {

struct PathWalkerOptions {
  int count = 0;        // people
  double radius = 0.2;  // m: a person's body at a scanner's height
  double speed = 1.0;   // m/s: the mean pace; each walks at 0.7-1.3 of it
  double side = 0.3;    // m: each keeps to a side of the path, at most this far from it
  // m: nobody stands closer than this to the scanner (it would be inside them).
  double clearance = 0.3;
  uint64_t seed = 1;
};

class PathWalkers {
 public:
  // `path`: the laser poses in order, `stamps` their times (s, non-decreasing, as many). Throws
  // navd::Error (kInvalidArgument) when they differ in count or are empty, or an option is out of
  // range (count or radius below 0, speed or side or clearance below 0).
  PathWalkers(const std::vector<Pose2>& path, const std::vector<double>& stamps, const PathWalkerOptions& options);
  // Where everyone is at time `t` (s), leaving out whoever is within `clearance` of `scanner`.
  std::vector<Disc> At(double t, const Point2& scanner) const;
  double path_length() const { return arc_.empty() ? 0.0 : arc_.back(); }

 private:
  struct Walker {
    double start = 0.0;  // m along the path at the first stamp
    double pace = 0.0;   // m/s along it, negative towards its start
    double side = 0.0;   // m to the left of it
  };
  // The point `side` metres to the left of the path, `along` metres from its start.
  Point2 PointAt(double along, double side) const;

  PathWalkerOptions o_;
  std::vector<Point2> points_;
  std::vector<double> arc_;  // m of path up to each point
  double t0_ = 0.0;
  std::vector<Walker> walkers_;
};

}  // namespace navd::mapping
