#pragma once
// The likelihood-field sensor model (Thrun, Burgard and Fox, "Probabilistic Robotics" §6.4) on a
// map's exact distance field: a beam ending d metres from the nearest obstacle surface has
// likelihood z_hit N(d; 0, sigma_hit) + z_rand / range_max. The same field serves the particle
// filter (log-likelihoods), the scan-to-map fit (distances and their gradients) and the histogram
// filter. Distances are to the obstacle *surface* (centre distance minus half a cell), bilinearly
// interpolated, so fits are not quantised to cells. Metres, map frame.
#include <algorithm>
#include <cmath>
#include <mutex>
#include <vector>

#include "services/common/occupancy_grid.h"
#include "services/common/pose2.h"

namespace navd::localization {

struct LikelihoodFieldOptions {
  double sigma_hit = 0.07;  // m
  double z_hit = 0.95;
  double z_rand = 0.05;
  double max_distance = 2.0;  // m: distances beyond count as this far
  double range_max = 4.0;     // m: the z_rand density is 1 / range_max
};

class LikelihoodField {
 public:
  LikelihoodField(const OccupancyGrid& map, const LikelihoodFieldOptions& options = {});

  // Log-likelihood of a beam ending at (gx, gy) in cells of the map, shifted by half a cell (so
  // cell centres are integers): ToCellX/ToCellY. Inline: particle filters run it particles x
  // beams times per scan, in float.
  [[gnu::always_inline]] float LogLikelihoodAtCell(float gx, float gy) const {
    if (!(gx >= -0.5f && gy >= -0.5f && gx < width_ - 0.5f && gy < height_ - 0.5f)) return log_outside_;
    // In the padded field, cell (x, y) is at (x + 1, y + 1): no clamping of indices or weights.
    const float px = gx + 1.0f, py = gy + 1.0f;
    const int x0 = static_cast<int>(px), y0 = static_cast<int>(py);
    const float fx = px - x0, fy = py - y0;
    const float* row0 = &surface_distance_[static_cast<size_t>(y0) * padded_width_ + x0];
    const float* row1 = row0 + padded_width_;
    const float d = (1 - fy) * ((1 - fx) * row0[0] + fx * row0[1]) + fy * ((1 - fx) * row1[0] + fx * row1[1]);
    const size_t mm = std::min(static_cast<size_t>(std::abs(d) * 1000.0f), log_likelihood_table_.size() - 1);
    return log_likelihood_table_[mm];
  }
  float ToCellX(double x) const { return static_cast<float>((x - origin_.x()) * inv_resolution_) - 0.5f; }
  float ToCellY(double y) const { return static_cast<float>((y - origin_.y()) * inv_resolution_) - 0.5f; }
  double inv_resolution() const { return inv_resolution_; }

  // Signed metres from the map-frame point p to the nearest obstacle surface (inside an obstacle,
  // minus the distance to its free side, so fits are pushed out of walls), at most max_distance,
  // with its gradient (per metre) when `gradient` is given; false off the map.
  bool SurfaceDistance(const Point2& p, double* distance, Point2* gradient = nullptr) const;
  // Builds the depths inside obstacles that SurfaceDistance reads (a distance transform of the
  // whole map; otherwise built on its first call), for owners that must not pay for it at their
  // first scan: on a large map it takes half a second, which a control loop cannot spare.
  void PrepareSurfaceDistance() const { SignedDistance(); }
  // How well a scan (end points in the robot frame) agrees with the map at `pose`, 0..1: the mean
  // over the beams of each beam's likelihood relative to a perfect fit. A mean of ratios, not of
  // logs: a few beams on people or clutter lower it by their share, they do not sink it (which
  // made real scans look "lost"), while a wrong pose, where most beams miss, still scores near 0.
  double Agreement(const Pose2& pose, const std::vector<Point2>& ends) const;
  // The log-likelihood of a perfect fit (d = 0): quality figures compare with it.
  double best_log_likelihood() const { return log_likelihood_table_[0]; }
  const LikelihoodFieldOptions& options() const { return o_; }

 private:
  LikelihoodFieldOptions o_;
  int width_ = 0, height_ = 0;
  Point2 origin_;
  double resolution_ = 1.0, inv_resolution_ = 1.0;
  // -half a cell anywhere inside obstacles (AMCL's field), with a ring of one cell repeating the
  // edge, (width + 2) x (height + 2).
  std::vector<float> surface_distance_;
  int padded_width_ = 0;
  // The same outside, the depth inside obstacles; unpadded, built on first use.
  const std::vector<float>& SignedDistance() const;
  mutable std::once_flag signed_once_;
  mutable std::vector<float> signed_distance_;
  std::vector<float> log_likelihood_table_;  // log(z_hit * N(d) + z_rand / range) by |d| in mm
  float log_outside_ = 0.0f;                 // a beam ending outside the map
};

}  // namespace navd::localization
