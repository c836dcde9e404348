#pragma once
// A depth camera's cloud to what stands in the robot's way, with PCL (the only file that includes
// it is obstacle_cloud_filter.cpp): the points go to the robot frame by the camera's mount, are cut
// to the heights that matter (PassThrough), thinned to one per voxel (VoxelGrid), the floor is
// found as a level plane near z = 0 by RANSAC (SACSegmentation) and split off, and lone points
// left above it are dropped as speckle (RadiusOutlierRemoval's test, a radius search per point, run on
// PCL's octree: the kd-tree that filter builds starts an OpenMP region per query, which costs more
// than the search on a few hundred points). What remains between min_height and the robot's top is
// an obstacle.
// Units: metres; robot frame (x ahead, y left, z up from the floor).
#include <Eigen/Core>
#include <functional>
#include <vector>

#include "services/common/world.h"

namespace navd::perception {

struct ObstacleCloudFilterOptions {
  double voxel = 0.05;       // m, VoxelGrid leaf
  double min_height = 0.05;  // m above the floor: lower is floor (a kerb, a threshold, a cable)
  double max_height = 0.5;   // m: the robot's top (and a margin); higher passes over it
  // The floor plane: points within floor_search of z = 0 are searched (so a table top is never
  // taken for it), the plane may tilt floor_max_tilt (rad) from level, and points within
  // floor_tolerance of it are floor.
  double floor_search = 0.12;
  double floor_max_tilt = 10.0 * M_PI / 180.0;
  double floor_tolerance = 0.03;
  int floor_iterations = 60;
  int floor_min_points = 30;  // fewer near-floor points: no plane is fitted, z = 0 is taken
  int floor_sample = 1000;    // at most this many near-floor points are searched
  // Depth noise grows with range squared: a point is an obstacle only if it stands clear of the
  // floor by min_height plus this many standard deviations of the camera's noise at its range.
  double noise_sigmas = 3.0;
  // Speckle: an obstacle point with fewer than speckle_neighbours others within speckle_radius.
  double speckle_radius = 0.12;
  int speckle_neighbours = 2;
};

struct FilteredCloud {
  std::vector<Eigen::Vector3f> obstacles;                     // robot frame
  std::vector<Eigen::Vector3f> floor;                         // robot frame: ends of rays through free space
  bool floor_fitted = false;                                  // a plane was found (else z = 0 was taken)
  Eigen::Vector4f floor_plane = Eigen::Vector4f(0, 0, 1, 0);  // a x + b y + c z + d = 0, robot frame
};

class ObstacleCloudFilter {
 public:
  // Throws navd::Error(kInvalidArgument) for options out of their ranges.
  ObstacleCloudFilter(const ObstacleCloudFilterOptions& options, const DepthCameraDescription& camera);
  // Whether an obstacle point (robot frame) is one the map already holds (a wall), so neither the
  // speckle test nor the layer need spend anything on it.
  using Explained = std::function<bool(const Eigen::Vector3f&)>;
  // `points`: the camera's, in its optical frame. Deterministic for the same points.
  FilteredCloud Filter(const std::vector<Eigen::Vector3f>& points, const Explained& explained = {}) const;
  const ObstacleCloudFilterOptions& options() const { return o_; }

 private:
  ObstacleCloudFilterOptions o_;
  DepthCameraDescription camera_;
};

}  // namespace navd::perception
