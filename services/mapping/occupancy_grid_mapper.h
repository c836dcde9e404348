#pragma once
// Occupancy grid mapping with known poses. Two update rules:
//  - Bayesian log-odds (seed 002 section 2.2, Elfes): each laser beam lowers the log-odds of the
//    cells it crosses (free) and raises the cell it ends in (occupied). A hit weighs about three
//    misses (as gmapping's and ROS map_server's 0.25 hit-rate threshold, Cartographer's hit/miss
//    probabilities): real scanners graze walls at shallow angles, and beams that pass a wall
//    cell by a hair must not erase what direct hits found. A no-return reading (at or beyond the
//    scanner's maximum) marks nothing and clears only missing_data_ray_length (Cartographer's
//    idea): the beam left the scanner but nothing says how far the free space reaches;
//  - HIMM (Borenstein's Histogramic In-Motion Mapping, book chapter 4): an integer certainty
//    0..15 per cell, +3 where a reading ends, -1 where it passed.
// Sonar readings use a cone inverse sensor model (Moravec and Elfes 1985, as seed 002's robots):
// free inside the cone short of the reading, occupied on its arc, both weighted down towards the
// cone's edge; under HIMM only the acoustic axis is updated, as Borenstein's original. A local map
// (robot-centred, e.g. one sensor sweep) fuses into the global one by seed 002's interpolation:
// each global cell takes the local occupancy at its position, interpolated from the four nearest
// local cells, through the Bayes update. Map frame, metres, radians.
#include <limits>
#include <vector>

#include "services/common/occupancy_grid.h"
#include "services/common/pose2.h"

namespace navd::mapping {

enum class MapUpdateRule { kLogOdds, kHimm };

struct MapperOptions {
  MapUpdateRule rule = MapUpdateRule::kLogOdds;
  double resolution = 0.05;          // m
  double l_occupied = 0.85;          // log-odds added at a hit (p 0.70: one hit marks a cell occupied)
  double l_free = -0.28;             // log-odds added along a beam (p 0.43: about three misses undo a hit)
  double l_min = -4.0, l_max = 4.0;  // clamps keep the map responsive to change
  double max_range = 50.0;           // m: longer readings are no-returns
  double usable_range = 15.0;        // m: beams are cut here (long beams are mostly noise); marks nothing,
  double far_usable_range = 50.0;    // except in a scan with fewer than min_near_echoes within
  int min_near_echoes = 60;  // usable_range (an open hall's; a share beyond 361 beams): cut this far (ScanReach)
  double missing_data_ray_length = 5.0;  // m cleared along a no-return reading
  double l_free_sonar = -0.4;            // log-odds along a sonar cone's axis, weighted down off it (Elfes)
};

// The cell size (m) for a map of the extent min..max: `resolution`, or where that would need more
// than OccupancyGrid::kMaxCells cells (a campus, kilometres of corridor), the finest size, in
// steps of 5 mm, that needs no more (up to 1 m: an extent wider still, or not finite, keeps
// `resolution`, and the mapper refuses it). For maps whose extent the data decide, not the user.
double ResolutionToFit(const Point2& min, const Point2& max, double resolution);

// How far a scan's beams are traced at most (m): usable_range, or far_usable_range for a scan that
// finds too little within it (services/common/scan_reach.h).
double ScanReachOf(const MapperOptions& options, const std::vector<float>& ranges, double range_max);
// How far along its beam a reading (IsReading) is traced (m): a no-return (at or beyond range_max)
// missing_data_ray_length, an echo its range; either cut at the scan's `reach` (ScanReachOf).
double TracedLength(const MapperOptions& options, double range, double range_max, double reach);

class OccupancyGridMapper {
 public:
  // `min`/`max`: the map-frame extent to cover (e.g. the poses' bounding box plus the range).
  OccupancyGridMapper(const Point2& min, const Point2& max, const MapperOptions& options = {});
  // The same size, origin and resolution as `geometry` (its cells are not read).
  OccupancyGridMapper(const OccupancyGrid& geometry, const MapperOptions& options);
  // Integrates a scan taken from `laser_pose`; beam i at angle_min + i * increment. Readings at or
  // beyond `range_max` (the scanner's own, when it reports one) or max_range are no-returns: they
  // mark nothing and clear missing_data_ray_length; so does +inf (ROS's no-return). Readings
  // shorter than kMinEchoRange (a scanner's error codes), -inf and NaN mark and clear nothing.
  void AddScan(const Pose2& laser_pose, const std::vector<float>& ranges, double angle_min, double increment,
               double range_max = std::numeric_limits<double>::infinity());
  // Integrates one sonar reading from `sensor_pose` (axis along its heading) with a cone of
  // `half_angle` radians; ranges >= max_range are no-returns (clear only).
  void AddSonar(const Pose2& sensor_pose, double range, double half_angle, double max_range);
  // Fuses a local map whose cell (0, 0) corner sits at `local_pose` (its x axis along the pose's
  // heading): seed 002's interpolated local occupancy enters each overlapping global cell through
  // the Bayes update (log-odds rule only; unknown local cells are skipped).
  void FuseLocalMap(const OccupancyGrid& local, const Pose2& local_pose);
  // The map's geometry (size, origin, resolution).
  const OccupancyGrid& geometry() const { return geometry_; }
  // Probabilities as map cells: 0..100, -1 where no beam ever reached.
  OccupancyGrid ToGrid() const;

 private:
  OccupancyGrid geometry_;  // size, origin and resolution only
  MapperOptions o_;
  void Update(size_t cell, double log_odds, int himm);  // one observation of a cell
  // One free observation of every cell a beam crosses from `from` to `to` (map frame) except
  // the cell at flat index `skip` (-1: none).
  void ClearBeam(const Point2& from, const Point2& to, long skip);
  std::vector<float> log_odds_;  // log-odds, or the HIMM certainty 0..15
  std::vector<uint8_t> seen_;
};

}  // namespace navd::mapping
