#pragma once
// Grid (histogram) localisation: the belief is a probability per cell of a coarse (x, y, theta)
// grid over the map, updated as the D-strategy of book chapter 3 (Rodríguez Lucatero) updates its
// distribution over a graph's vertices:
//   predict  f'(v) = sum_u f(u) delta(u, a, v)       (a: the odometry's motion)
//   correct  f(v) ∝ f'(v) P(scan | v)                 (the chapter's colour match, here the
//                                                      likelihood field of the laser's beams)
// The chapter's delta moves to the commanded neighbour with probability p = 2/3 and to each of the
// two beside it with (1 - p) / 2 = 1/6; here the motion carries each cell's mass by the odometry's
// increment (split between the cells it lands between) and then spreads it with that kernel along
// x, y and theta. It needs no prior (uniform over free space: global localisation) and holds any
// number of hypotheses, at a cost that grows with the map's area: for small maps. Metres,
// radians, map frame.
#include <memory>
#include <mutex>
#include <vector>

#include "services/common/occupancy_grid.h"
#include "services/localization/likelihood_field.h"
#include "services/localization/localizer.h"
#include "services/localization/odometry_history.h"

namespace navd::localization {

struct HistogramOptions {
  double cell_size = 0.1;            // m
  int heading_bins = 36;             // 10 degrees each
  double kernel_centre = 2.0 / 3.0;  // the chapter's p; each neighbour gets (1 - p) / 2
  int beams = 30;                    // beams used per scan, evenly spread
  // Beams of one scan are far from independent: their summed log-likelihood is scaled by this.
  double likelihood_scale = 0.2;
  size_t max_states = 4000000;  // larger grids are refused: use the particle filter
  // States whose probability falls under this fraction of the most likely one are dropped, so a
  // converged belief costs a few hundred states per scan instead of the whole grid.
  double prune_below = 1e-9;
  LikelihoodFieldOptions field;
};

class HistogramLocalizer : public Localizer {
 public:
  // Throws navd::Error(kInvalidArgument) when the grid would exceed max_states. Starts uniform
  // over the free cells.
  HistogramLocalizer(const OccupancyGrid& map, const HistogramOptions& options = {});
  std::string name() const override { return "histogram"; }
  void AddOdometry(const OdometryReading& reading) override;
  bool AddScan(const ScanReading& scan) override;
  PoseEstimate Estimate() const override;
  bool GlobalRelocalize() override;
  // Lays the grid out over `map` and spreads the belief round the current estimate. A map larger
  // than max_states allows at the requested cell_size gets coarser cells (the robot is running:
  // refusing would leave it on the old map).
  bool SetMap(const OccupancyGrid& map) override;
  // Needs the laser; the slowest method, recovers like the particle filter (every pose is held
  // until the scans rule it out), precise to a fraction of a cell.
  MethodContext Suitability(bool laser_fresh) const override;

  // The belief's marginal over x cells (for tests): probability per column.
  std::vector<double> MarginalX() const;
  int cells_x() const { return nx_; }
  // The grid column whose centre is nearest to x (map frame).
  int ColumnOf(double x) const;

 private:
  void ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) override;
  bool CanSearch() const override { return true; }
  void Predict(const Pose2& increment);
  void Blur();
  void Normalise();
  void UpdateEstimateLocked();
  size_t Index(int i, int j, int k) const { return (static_cast<size_t>(k) * ny_ + j) * nx_ + i; }
  // Bin k is centred on -pi + k * bin (so 0 and the axes are bin centres).
  double HeadingOf(int k) const { return -M_PI + k * bin_; }

  // The grid over `map` (origin, size, free cells) for options `o`; with the mutex held.
  void LayOutLocked(const OccupancyGrid& map, const HistogramOptions& o, std::unique_ptr<const LikelihoodField> field);
  void ResetPoseLocked(const Pose2& pose, const Eigen::Matrix3d& covariance);
  void GlobalRelocalizeLocked();

  const HistogramOptions requested_;
  HistogramOptions o_;  // in effect: SetMap may coarsen the cells of a larger map
  std::unique_ptr<const LikelihoodField> field_;
  Point2 origin_;
  int nx_ = 0, ny_ = 0, nk_ = 0;
  double bin_ = 0.0;
  std::vector<uint8_t> free_;  // per (i, j): the cell centre lies in free space
  mutable std::mutex mutex_;
  std::vector<float> belief_;
  std::vector<float> scratch_;
  OdometryHistory odom_history_;
  bool have_odom_ = false;
  Pose2 predicted_at_odom_;  // odometry up to which the belief has been moved
  bool moved_since_scan_ = true;
  PoseEstimate estimate_;
};

}  // namespace navd::localization
