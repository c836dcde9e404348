#pragma once
// Correlative scan matching (Olson 2009, as in Karto and Cartographer's real-time matcher): the
// reference points are smeared into a lookup grid, each cell holding exp(-d²/2σ²) for the distance
// d to the nearest reference point, and a scan is scored at every pose of a search window as the
// mean lookup value of its points. The search is coarse to fine: whole cells and coarse angles
// first over the whole window, then a sub-cell, sub-step search (bilinear lookups) around the best
// few coarse poses. Map frame, metres, radians.
#include <cmath>
#include <vector>

#include "services/common/pose2.h"

namespace navd::mapping {

struct ScanMatchOptions {
  double resolution = 0.05;    // m, lookup cells
  double sigma = 0.05;         // m, smear of each reference point
  double window_xy = 0.25;     // m, half-size of the translational window
  double window_theta = 0.15;  // rad, half-size of the angular window
  double angle_step = 0.01;    // rad, coarse angular step
  int refine_candidates = 3;   // coarse poses refined
  // A prior on the offset from `prior` (Cartographer's real-time matcher weighs its candidates
  // the same way): scores are ranked after multiplying by exp(-d²/2σ_xy² - Δθ²/2σ_θ²), so along a
  // corridor, where the scan fits equally well anywhere, the odometry's guess wins instead of
  // whichever end of the window the search reached first. 0: no prior.
  double prior_sigma_xy = 0.0;     // m
  double prior_sigma_theta = 0.0;  // rad
  // Poses at least this far (m) from the best count as another place: the best coarse score among
  // them is reported, so callers can refuse ambiguous matches (corridors). 0: not computed.
  double distinct_xy = 0.0;
  // Likewise poses turned at least this far (rad) from the best: a room seen from its middle can
  // fit nearly as well turned by a few degrees. 0: headings are not judged apart.
  double distinct_theta = 0.0;

  // This window grown by the given factors, its prior in proportion (a prior as wide, relative to
  // its window, as before).
  ScanMatchOptions Widened(double grow_xy, double grow_theta) const {
    ScanMatchOptions out = *this;
    out.window_xy *= grow_xy;
    out.prior_sigma_xy *= grow_xy;
    out.window_theta *= grow_theta;
    out.prior_sigma_theta *= grow_theta;
    return out;
  }
};

struct ScanMatch {
  Pose2 pose;
  double score = 0.0;  // mean lookup value of the scan's points, 0..1 (before any prior)
  // The best coarse score at least distinct_xy from the best coarse pose, and that best coarse
  // score (comparable with each other, not with `score`).
  double coarse_best = 0.0, coarse_elsewhere = 0.0;
  // How far (m) from the best coarse pose poses scoring within 5% of it reach: a long plateau
  // means the scan slides along a corridor.
  double coarse_spread = 0.0;
};

// A lookup grid over reference points (world frame).
class CorrelationGrid {
 public:
  // Its cells are taken from, and handed back to, RecycledCells.
  CorrelationGrid(const std::vector<Point2>& reference, double resolution, double sigma);
  CorrelationGrid(const CorrelationGrid&) = default;
  CorrelationGrid(CorrelationGrid&&) = default;
  CorrelationGrid& operator=(const CorrelationGrid&) = default;
  CorrelationGrid& operator=(CorrelationGrid&&) = default;
  ~CorrelationGrid();
  // A world coordinate in cell units from cell (0, 0)'s centre: cell centres are the sample
  // points of the fine search's bilinear lookups.
  double CellUnitsX(double x) const { return (x - origin_.x()) / resolution_ - 0.5; }
  double CellUnitsY(double y) const { return (y - origin_.y()) / resolution_ - 0.5; }
  // Lookup of the cell holding a world point, by integer cell (0 outside).
  float AtCell(int x, int y) const {
    return x >= 0 && y >= 0 && x < width_ && y < height_ ? cells_[static_cast<size_t>(y) * width_ + x] : 0.0f;
  }
  // Row y's cells, x = 0 first (0 <= y < height()).
  const float* Row(int y) const { return &cells_[static_cast<size_t>(y) * width_]; }
  int width() const { return width_; }
  int height() const { return height_; }
  int CellX(double x) const { return static_cast<int>(std::floor((x - origin_.x()) / resolution_)); }
  int CellY(double y) const { return static_cast<int>(std::floor((y - origin_.y()) / resolution_)); }
  double resolution() const { return resolution_; }
  bool empty() const { return cells_.empty(); }

 private:
  double resolution_;
  Point2 origin_ = Point2::Zero();  // world position of cell (0, 0)'s corner
  int width_ = 0, height_ = 0;
  std::vector<float> cells_;
};

// The best pose within the window around `prior` for `points` (robot frame) on `grid`.
ScanMatch MatchScan(const CorrelationGrid& grid, const std::vector<Point2>& points, const Pose2& prior,
                    const ScanMatchOptions& options);

// Points at least `spacing` metres apart (the first of each close group kept): an even sample of a
// scan for matching, however its beams bunch up near walls.
std::vector<Point2> ThinPoints(const std::vector<Point2>& points, double spacing);

// Cartographer's adaptive voxel filter, along the scan: `points` thinned (ThinPoints) at the
// widest spacing, up to `max_spacing` m, that keeps at least `min_points` of them; as they are
// when there are no more than that. A scanner with many beams costs what one with min_points does,
// and one with fewer loses none.
std::vector<Point2> ThinPointsTo(const std::vector<Point2>& points, size_t min_points, double max_spacing);

}  // namespace navd::mapping
