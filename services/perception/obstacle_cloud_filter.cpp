#include "services/perception/obstacle_cloud_filter.h"

#include <pcl/filters/extract_indices.h>
#include <pcl/filters/passthrough.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/search/octree.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <cmath>

#include "services/common/camera_frame.h"
#include "services/common/error.h"

namespace navd::perception {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

ObstacleCloudFilter::ObstacleCloudFilter(const ObstacleCloudFilterOptions& options,
                                         const DepthCameraDescription& camera)
    : o_(options), camera_(camera) {
  if (!(o_.voxel > 0.0) || !(o_.max_height > o_.min_height) || !(o_.floor_search > 0.0) ||
      !(o_.floor_tolerance > 0.0) || o_.floor_iterations < 1 || o_.floor_sample < 3 || !(o_.speckle_radius > 0.0) ||
      o_.speckle_neighbours < 0)
    throw Error(ErrorCode::kInvalidArgument,
                "obstacle cloud filter: voxel, floor_search, floor_tolerance and speckle_radius must be > 0 m, "
                "max_height above min_height, floor_iterations >= 1, floor_sample >= 3, speckle_neighbours >= 0");
}

FilteredCloud ObstacleCloudFilter::Filter(const std::vector<Eigen::Vector3f>& points,
                                          const Explained& explained) const {
  FilteredCloud out;
  const Eigen::Isometry3f to_robot = RobotFromOptical(camera_);
  auto robot = std::make_shared<Cloud>();
  robot->reserve(points.size());
  for (const Eigen::Vector3f& p : points) {
    const Eigen::Vector3f r = to_robot * p;
    robot->push_back(pcl::PointXYZ(r.x(), r.y(), r.z()));
  }
  // Heights that matter: from below the floor (it may sit a little low) to the robot's top.
  auto band = std::make_shared<Cloud>();
  pcl::PassThrough<pcl::PointXYZ> pass;
  pass.setInputCloud(robot);
  pass.setFilterFieldName("z");
  pass.setFilterLimits(static_cast<float>(-o_.floor_search), static_cast<float>(o_.max_height));
  pass.filter(*band);
  if (band->empty()) return out;
  auto thin = std::make_shared<Cloud>();
  pcl::VoxelGrid<pcl::PointXYZ> voxels;
  voxels.setInputCloud(band);
  const auto leaf = static_cast<float>(o_.voxel);
  voxels.setLeafSize(leaf, leaf, leaf);
  voxels.filter(*thin);

  // The floor: a level plane among the points near z = 0.
  // RANSAC needs far fewer points than a camera gives to find a plane most of them lie on: at most
  // floor_sample of them, spread evenly.
  pcl::IndicesPtr near_floor(new pcl::Indices);
  for (size_t i = 0; i < thin->size(); ++i)
    if (std::abs((*thin)[i].z) <= o_.floor_search) near_floor->push_back(static_cast<int>(i));
  if (static_cast<int>(near_floor->size()) > o_.floor_sample) {
    const size_t every = near_floor->size() / static_cast<size_t>(o_.floor_sample) + 1;
    size_t kept = 0;
    for (size_t i = 0; i < near_floor->size(); i += every) (*near_floor)[kept++] = (*near_floor)[i];
    near_floor->resize(kept);
  }
  if (static_cast<int>(near_floor->size()) >= o_.floor_min_points) {
    pcl::SACSegmentation<pcl::PointXYZ> sac;
    sac.setOptimizeCoefficients(true);
    sac.setModelType(pcl::SACMODEL_PERPENDICULAR_PLANE);
    sac.setAxis(Eigen::Vector3f::UnitZ());
    sac.setEpsAngle(o_.floor_max_tilt);
    sac.setMethodType(pcl::SAC_RANSAC);
    sac.setDistanceThreshold(o_.floor_tolerance);
    sac.setMaxIterations(o_.floor_iterations);
    sac.setInputCloud(thin);
    sac.setIndices(near_floor);
    pcl::PointIndices inliers;
    pcl::ModelCoefficients plane;
    sac.segment(inliers, plane);
    if (plane.values.size() == 4 && static_cast<int>(inliers.indices.size()) >= o_.floor_min_points) {
      Eigen::Vector4f p(plane.values[0], plane.values[1], plane.values[2], plane.values[3]);
      if (p.z() < 0) p = -p;  // normal up
      p /= p.head<3>().norm();
      if (std::abs(p.w()) <= o_.floor_search) {
        out.floor_plane = p;
        out.floor_fitted = true;
      }
    }
  }
  // Each point by its height over the floor plane; obstacles must clear the noise at their range.
  auto candidates = std::make_shared<Cloud>();
  const Eigen::Vector3f camera(static_cast<float>(camera_.mount_x), static_cast<float>(camera_.mount_y),
                               static_cast<float>(camera_.mount_z));
  for (const pcl::PointXYZ& q : *thin) {
    const Eigen::Vector3f v(q.x, q.y, q.z);
    const double height = out.floor_plane.head<3>().dot(v) + out.floor_plane.w();
    const double range = (v - camera).norm();
    const double clear = o_.min_height + o_.noise_sigmas * camera_.noise * range * range;
    if (std::abs(height) <= std::max(o_.floor_tolerance, clear - o_.min_height)) {
      out.floor.push_back(v);
    } else if (height >= clear && v.z() <= o_.max_height && !(explained && explained(v))) {
      candidates->push_back(q);
    }
  }

  if (candidates->empty()) return out;
  Cloud kept;
  if (o_.speckle_neighbours > 0) {
    pcl::search::Octree<pcl::PointXYZ> near(o_.speckle_radius);
    near.setInputCloud(candidates);
    pcl::Indices found;
    std::vector<float> distances;
    const unsigned int enough = static_cast<unsigned int>(o_.speckle_neighbours) + 1;  // the point itself too
    for (const pcl::PointXYZ& q : *candidates)
      if (near.radiusSearch(q, o_.speckle_radius, found, distances, enough) >= static_cast<int>(enough))
        kept.push_back(q);
  } else {
    kept = *candidates;
  }
  out.obstacles.reserve(kept.size());
  for (const pcl::PointXYZ& q : kept) out.obstacles.emplace_back(q.x, q.y, q.z);
  return out;
}

}  // namespace navd::perception
