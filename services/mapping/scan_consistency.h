#pragma once
// How well a trajectory's scans agree with one another, without ground truth: each return, placed
// in the map frame by its scan's pose, is measured against the line that the other scans' returns
// around it draw (their principal direction within neighbour_radius), as the point-to-plane
// "mean plane variance" of 3-D registration benchmarks does. A trajectory that puts the scans where
// they were taken draws every wall once, thin; one that errs draws it twice, or thick. It judges
// SLAM on a robot's own log (no corrected poses), and a corrected log's poses themselves: they come
// from another SLAM system, with errors of their own. Map frame, metres.
#include <unordered_map>
#include <utility>
#include <vector>

#include "services/common/pose2.h"

namespace navd::mapping {

struct ScanConsistencyOptions {
  double neighbour_radius = 0.15;  // m: the other scans' returns this close to a return draw its line
  int min_neighbours = 6;          // fewer, and the return has no line (nothing else saw the place)
  // A neighbourhood whose spread across its line is more than this share of the spread along it
  // (a corner, a plant, a person) has no line either.
  double max_flatness = 0.1;
  // m: a return farther from its line counts this much: one that moved (a door, a person) or one
  // the neighbourhood's line misses costs a bounded amount, whatever its distance.
  double cap = 0.05;
  // Scans closer than this in the log on either side are not neighbours: they see a wall from
  // nearly the same place, through the same beams, with the same error of the chain that carries
  // them, and would agree with the scan wherever the trajectory put the two.
  int exclude_scans = 10;
};

struct ScanConsistencyResult {
  double mean_distance = 0.0;  // m: the mean capped distance of the returns with a line to it; NaN: none
  long long scored = 0;        // returns with a line
  // Per scan, in order: its scored returns' mean distance (m; NaN where none was scored) and count.
  std::vector<double> scan_mean_distance;
  std::vector<int> scan_scored;
};

class ScanConsistency {
 public:
  // `returns[i]`: scan i's echoes in its robot frame (ScanReturns), at `poses[i]` in the map frame.
  // Throws Error(kInvalidArgument) when the two differ in length.
  ScanConsistency(const std::vector<Pose2>& poses, std::vector<std::vector<Point2>> returns,
                  const ScanConsistencyOptions& options = {});

  // Every scan's returns against the lines of the others.
  ScanConsistencyResult Score() const;
  // Scan `k`'s returns placed at `pose` instead, against the lines of the others: the mean capped
  // distance (m; NaN when none has a line) of those with a line there, and their count. For finding
  // where the other scans place one scan.
  struct ScanFit {
    double mean_distance = 0.0;
    int scored = 0;
  };
  ScanFit ScanAt(int k, const Pose2& pose) const;

 private:
  struct Placed {
    Point2 point;
    int scan;
  };
  // The capped distance (m) from `point` of scan `scan` to the line of the other scans' returns
  // around it; negative when they draw none.
  double DistanceToLine(const Point2& point, int scan) const;
  static constexpr int kCellsPerRadius = 2;
  // The cell (neighbour_radius / kCellsPerRadius wide) a coordinate (m) falls in.
  int64_t Cell(double v) const;

  ScanConsistencyOptions o_;
  std::vector<std::vector<Point2>> returns_;
  std::vector<Placed> placed_;  // every scan's returns in the map frame, grouped by cell
  // A cell's returns: [first, second) in placed_.
  std::unordered_map<int64_t, std::pair<int, int>> cells_;
};

}  // namespace navd::mapping
