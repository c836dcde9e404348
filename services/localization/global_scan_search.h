#pragma once
// Where on the whole map could a scan have been taken? A correlative search over the whole map,
// after Olson's multi-resolution matching and the branch-and-bound search Cartographer runs for
// loop closures. Every block of free space and heading step gets a score against a field whose
// cells hold the best score within half a block, so a block's score bounds what any pose inside
// it can score. Blocks are grouped into a pyramid (each level's blocks twice as wide, its field
// pooled over twice the width, so a parent's score bounds its children's), searched best first:
// the first blocks_refined finest blocks to come out are exactly the best of an exhaustive scan
// of every finest block, found in a fraction of the lookups. Those blocks are then searched cell
// by cell. A particle filter scattering particles uniformly needs many scans to gather where the
// robot is; these few candidates hold it after one, and the filter's next scans tell look-alike
// places apart.
// Units: metres, radians; poses in the map frame, scan points in the robot frame.
#include <cstdint>
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
  // Levels of the block pyramid above the finest blocks (1: the finest blocks only, scored
  // exhaustively). Each level doubles the block width; the result does not depend on it.
  int pyramid_levels = 4;
};

struct PoseCandidate {
  Pose2 pose;
  double score = 0.0;  // 0..1: the mean over the points of each one's likelihood relative to a perfect fit
};

class GlobalScanSearch {
 public:
  // Keeps a reference to `field`, which must outlive the search and be built on `map`.
  GlobalScanSearch(const OccupancyGrid& map, const LikelihoodField& field, const GlobalScanSearchOptions& options = {});
  // The best distinct poses for a scan's end points, best first; empty for fewer than 5 points.
  std::vector<PoseCandidate> Search(const std::vector<Point2>& points) const;
  // Block scores computed by the last Search (all levels): what the pyramid saves.
  long last_block_scores() const { return last_block_scores_; }

 private:
  // One level of the pyramid: blocks of `cells` x `cells` map cells, which of them hold free
  // space, and the score field pooled over half a block.
  struct Level {
    int cells = 1;
    int half = 0;        // cells: the pooling's half width
    bool clamp = false;  // points off the map count their nearest edge cell (coarser levels: a bound)
    int blocks_x = 0, blocks_y = 0;
    std::vector<uint8_t> free;  // per block
    std::vector<float> bound;   // per map cell: the best per-point score within half a block and a margin
  };
  // Mean bound over the points (rotated, in cells) placed at block (bx, by) of `level`.
  float BlockScore(const Level& level, int bx, int by, const float* rx, const float* ry, size_t n) const;

  GlobalScanSearchOptions o_;
  const LikelihoodField& field_;
  int width_ = 0, height_ = 0;
  double resolution_ = 0.05;
  Point2 origin_;
  std::vector<float> score_;   // per map cell: exp(log-likelihood) relative to a perfect fit, 0..1
  std::vector<Level> levels_;  // finest first
  mutable long last_block_scores_ = 0;
};

}  // namespace navd::localization
