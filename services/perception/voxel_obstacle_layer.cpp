#include "services/perception/voxel_obstacle_layer.h"

#include <algorithm>
#include <cmath>

#include "services/common/error.h"
#include "services/common/grid_traversal.h"

namespace navd::perception {

VoxelObstacleLayer::VoxelObstacleLayer(const OccupancyGrid& geometry, const VoxelObstacleLayerOptions& options)
    : geometry_(geometry.width(), geometry.height(), geometry.resolution(), geometry.origin(), OccupancyGrid::kFree),
      o_(options),
      columns_(static_cast<size_t>(geometry.width()) * geometry.height(), 0),
      marked_at_(columns_.size(), 0.0f) {
  if (o_.slices < 1 || o_.slices > 32 || !(o_.slice > 0.0))
    throw Error(ErrorCode::kInvalidArgument, "voxel layer: slices must be 1 to 32 and slice > 0 m");
}

uint32_t VoxelObstacleLayer::SliceMask(double z0, double z1) const {
  if (z0 > z1) std::swap(z0, z1);
  const int top = o_.slices - 1;
  if (z1 < 0.0 || z0 > o_.slices * o_.slice) return 0;
  const int a = std::clamp(static_cast<int>(std::floor(z0 / o_.slice)), 0, top);
  const int b = std::clamp(static_cast<int>(std::floor(z1 / o_.slice)), 0, top);
  const uint32_t upto_b = b >= 31 ? 0xFFFFFFFFu : ((1u << (b + 1)) - 1u);
  return upto_b & ~((1u << a) - 1u);
}

void VoxelObstacleLayer::ClearRay(const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  const Point2 a = from.head<2>(), b = to.head<2>();
  const double length = (b - a).norm();
  const CellIndex end = geometry_.CellOf(b);
  // Each cell's slices between the heights where the ray enters it and leaves it; the end cell,
  // where the ray hit something (or the floor), is not cleared.
  bool have = false;
  CellIndex cell{0, 0};
  double entered = 0.0;
  auto height_at = [&](double t) { return length > 0.0 ? from.z() + (to.z() - from.z()) * (t / length) : to.z(); };
  auto clear = [&](double left) {
    if (!have || cell == end || !geometry_.Contains(cell)) return;
    uint32_t& column = columns_[Flat(cell)];
    const uint32_t cleared = column & ~SliceMask(height_at(entered), height_at(left));
    if (cleared != column) {
      column = cleared;
      ++version_;
    }
  };
  TraverseSegment(geometry_, a, b, [&](const CellIndex& c, double t) {
    clear(t);
    have = true;
    cell = c;
    entered = t;
    return true;
  });
  clear(length);
}

void VoxelObstacleLayer::Update(const Eigen::Vector3d& sensor, const std::vector<Eigen::Vector3d>& hits,
                                const std::vector<Eigen::Vector3d>& free_ends, double now) {
  if (!geometry_.ContainsPoint(sensor.head<2>())) return;
  for (const Eigen::Vector3d& p : free_ends) ClearRay(sensor, p);
  for (const Eigen::Vector3d& p : hits) ClearRay(sensor, p);
  for (const Eigen::Vector3d& p : hits) {
    const CellIndex c = geometry_.CellOf(p.head<2>());
    if (!geometry_.Contains(c)) continue;
    const uint32_t bit = SliceMask(p.z(), p.z());
    uint32_t& column = columns_[Flat(c)];
    if ((column & bit) != bit) ++version_;
    column |= bit;
    marked_at_[Flat(c)] = static_cast<float>(now);
  }
}

void VoxelObstacleLayer::Decay(double now) {
  for (size_t i = 0; i < columns_.size(); ++i) {
    if (columns_[i] != 0 && now - marked_at_[i] > o_.decay) {
      columns_[i] = 0;
      ++version_;
    }
  }
}

std::vector<Point2> VoxelObstacleLayer::Obstacles() const {
  std::vector<Point2> out;
  for (int y = 0; y < geometry_.height(); ++y)
    for (int x = 0; x < geometry_.width(); ++x)
      if (columns_[Flat({x, y})] != 0) out.push_back(geometry_.CellCenter({x, y}));
  return out;
}

size_t VoxelObstacleLayer::obstacle_count() const {
  return static_cast<size_t>(std::count_if(columns_.begin(), columns_.end(), [](uint32_t c) { return c != 0; }));
}

}  // namespace navd::perception
