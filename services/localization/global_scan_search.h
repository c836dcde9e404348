#pragma once
// Where on the whole map could a scan have been taken? An exhaustive correlative search in two
// levels, after Olson's multi-resolution matching and the branch-and-bound search Cartographer
// runs for loop closures: every coarse block of free space and every heading step is scored
// against a field whose cells hold the best score within half a block (so a block's score bounds
// what any pose inside it can score), and the best blocks are then searched cell by cell. A
// particle filter scattering particles uniformly needs many scans to gather where the robot is;
// these few candidates hold it after one, and the filter's next scans tell look-alike places apart.
// Units: metres, radians; poses in the map frame, scan points in the robot frame.
#include <memory>
#include <vector>

#include "services/common/occupancy_grid.h"
#include "services/common/pose2.h"
#include "services/localization/likelihood_field.h"

namespace navd::localization {

struct GlobalScanSearchOptions {
  double block = 0.3;                      // m: the coarse level's step in x and y
  double angle_step = 2.0 * M_PI / 180.0;  // rad: the coarse level's heading step
  int points = 60;                         // scan points scored (evenly thinned)
  double max_range = 10.0;                 // m: farther points are left out (heading errors grow with range)
  int blocks_refined = 300;                // best coarse (block, heading) pairs searched finely
  int candidates = 40;                     // at most this many returned
  double distinct_xy = 0.4;                // m: candidates closer than this (and distinct_theta) are one
  double distinct_theta = 0.3;             // rad
};

// Where a search looks: positions within `radius` of `centre` and headings within `max_turn` of its
// heading. A whole-map search has none. A window holds few places, so fewer are refined.
struct SearchWindow {
  Pose2 centre;
  double radius = 5.0;      // m
  double max_turn = 0.6;    // rad
  int blocks_refined = 30;  // best coarse (block, heading) pairs searched finely
};

struct PoseCandidate {
  Pose2 pose;
  double score = 0.0;  // 0..1: the mean over the points of each one's likelihood relative to a perfect fit
};

class GlobalScanSearch {
 public:
  // Keeps references to `map` and `field` (built on `map`), which must outlive the search.
  GlobalScanSearch(const OccupancyGrid& map, const LikelihoodField& field, const GlobalScanSearchOptions& options = {});
  // The best distinct poses for a scan's end points (robot frame), best first, on the whole map or
  // within `window`; empty for fewer than 5 usable points.
  std::vector<PoseCandidate> Search(const std::vector<Point2>& points, const SearchWindow* window = nullptr) const;
  // How well the same points fit at `pose`, on the candidates' scale.
  double Score(const Pose2& pose, const std::vector<Point2>& points) const;
  // The share of the points that the scan, taken at `pose`, would have seen through a wall of the
  // map: their beams cross an occupied cell more than `margin` metres before they end. Long beams
  // count too: along a corridor, only the far ones contradict a pose a few metres off. People and carts in front of the
  // walls make a right pose fit poorly but leave this near 0; a scan taken elsewhere contradicts the map from a wrong
  // pose.
  double SeeThrough(const Pose2& pose, const std::vector<Point2>& points, double margin) const;

 private:
  // The points scored: finite, within max_range, thinned to o_.points.
  std::vector<Point2> Scored(const std::vector<Point2>& all_points) const;

  GlobalScanSearchOptions o_;
  const OccupancyGrid& map_;
  const LikelihoodField& field_;
  int width_ = 0, height_ = 0;
  int block_cells_ = 1;
  double resolution_ = 0.05;
  Point2 origin_;
  std::vector<float> bound_;    // per map cell: the best per-point score within half a block
  std::vector<Point2> blocks_;  // centres of the blocks holding free space
};

}  // namespace navd::localization
