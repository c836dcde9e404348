#include "services/perception/depth_obstacle_layer.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "services/common/camera_frame.h"

namespace navd::perception {

DepthObstacleLayerOptions DepthObstacleLayerOptions::ForRobot(double height) {
  DepthObstacleLayerOptions o;
  o.filter.max_height = height + 0.05;
  const int max_slices = 32;  // bits in a column
  o.layer.slice = std::max(o.layer.slice, o.filter.max_height / max_slices);
  o.layer.slices = std::clamp(static_cast<int>(std::ceil(o.filter.max_height / o.layer.slice)), 1, max_slices);
  return o;
}

DepthObstacleLayer::DepthObstacleLayer(const DepthCameraDescription& camera, const DepthObstacleLayerOptions& options)
    : filter_(options.filter, camera),
      camera_(camera),
      layer_options_(options.layer),
      // Neighbouring pixels closer together than a voxel even at the farthest range add nothing
      // the VoxelGrid keeps: a 640 x 480 D435 image is read every third row and column (1.5 cm
      // apart at 5 m against 5 cm voxels), the default 212 x 120 one whole.
      stride_(std::max(1, static_cast<int>(options.filter.voxel * IntrinsicsOf(camera).fx / camera.range_max))) {}

void DepthObstacleLayer::SetMap(const OccupancyGrid& map) {
  auto known = std::make_shared<OccupancyGrid>(map.width(), map.height(), map.resolution(), map.origin());
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x)
      if (map.IsOccupied({x, y}))
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            if (known->Contains({x + dx, y + dy})) known->set({x + dx, y + dy}, OccupancyGrid::kOccupied);
  std::lock_guard<std::mutex> lock(mutex_);
  known_ = std::move(known);
  const bool same_grid =
      layer_ && layer_->geometry().width() == map.width() && layer_->geometry().height() == map.height() &&
      layer_->geometry().resolution() == map.resolution() && layer_->geometry().origin() == map.origin();
  if (same_grid) return;
  layer_.emplace(map, layer_options_);
  obstacles_ = std::make_shared<const std::vector<Point2>>();
  ++version_;
}

void DepthObstacleLayer::AddCloud(const std::vector<Eigen::Vector3f>& points, const Pose2& robot, double now) {
  std::shared_ptr<const OccupancyGrid> known;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    known = known_;
  }
  if (!known) return;  // no map yet
  auto in_map = [&](const Eigen::Vector3f& p) {
    const CellIndex cell = known->CellOf(robot * Point2(p.x(), p.y()));
    return known->Contains(cell) && known->IsOccupied(cell);
  };
  DepthView view = DepthView::Of(points, IntrinsicsOf(camera_), camera_.width, camera_.height);
  // The filter needs no lock: it reads only its options.
  const std::vector<Eigen::Vector3f> thinned = stride_ > 1 ? view.Points(stride_) : std::vector<Eigen::Vector3f>{};
  const FilteredCloud seen = filter_.Filter(stride_ > 1 ? thinned : points, in_map);
  std::vector<Eigen::Vector3d> hits;
  hits.reserve(seen.obstacles.size());
  for (const Eigen::Vector3f& p : seen.obstacles) {
    const Point2 at = robot * Point2(p.x(), p.y());
    hits.emplace_back(at.x(), at.y(), p.z());
  }
  view.range_min = camera_.range_min;
  view.range_max = camera_.range_max;
  view.noise = camera_.noise;
  Eigen::Isometry3d map_from_robot = Eigen::Isometry3d::Identity();
  map_from_robot.linear() = Eigen::AngleAxisd(robot.theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  map_from_robot.translation() = Eigen::Vector3d(robot.x, robot.y, 0.0);
  view.map_from_optical = map_from_robot * RobotFromOptical(camera_).cast<double>();
  std::lock_guard<std::mutex> lock(mutex_);
  if (!layer_ || known != known_) return;  // the map changed while the cloud was filtered
  const uint64_t before = layer_->version();
  layer_->Update(view, hits, now);
  layer_->Decay(now);
  if (layer_->version() != before) {
    obstacles_ = std::make_shared<const std::vector<Point2>>(layer_->Obstacles());
    ++version_;
  }
}

std::shared_ptr<const std::vector<Point2>> DepthObstacleLayer::Obstacles() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return obstacles_;
}

uint64_t DepthObstacleLayer::version() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return version_;
}

}  // namespace navd::perception
