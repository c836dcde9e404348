#include "services/perception/voxel_obstacle_layer.h"

#include <cmath>
#include <limits>

#include "services/common/error.h"

namespace navd::perception {

DepthView DepthView::Of(const std::vector<Eigen::Vector3f>& points, const PinholeIntrinsics& k, int width, int height) {
  DepthView v;
  v.intrinsics = k;
  v.width = width;
  v.height = height;
  v.depth.assign(static_cast<size_t>(width) * height, std::numeric_limits<float>::infinity());
  const auto fx = static_cast<float>(k.fx), fy = static_cast<float>(k.fy), cx = static_cast<float>(k.cx),
             cy = static_cast<float>(k.cy);
  for (const Eigen::Vector3f& p : points) {
    if (!(p.z() > 0.0f)) continue;
    const float inverse = 1.0f / p.z();
    const float u = fx * p.x() * inverse + cx, w = fy * p.y() * inverse + cy;
    if (!(u >= 0.0f && w >= 0.0f && u < static_cast<float>(width) && w < static_cast<float>(height))) continue;
    float& d = v.depth[static_cast<size_t>(w) * width + static_cast<size_t>(u)];
    d = std::min(d, p.z());
  }
  return v;
}

std::vector<Eigen::Vector3f> DepthView::Points(int stride) const {
  std::vector<Eigen::Vector3f> out;
  const auto fx = static_cast<float>(intrinsics.fx), fy = static_cast<float>(intrinsics.fy),
             cx = static_cast<float>(intrinsics.cx), cy = static_cast<float>(intrinsics.cy);
  for (int v = 0; v < height; v += stride) {
    for (int u = 0; u < width; u += stride) {
      const float z = depth[static_cast<size_t>(v) * width + u];
      if (!std::isfinite(z)) continue;
      out.emplace_back((static_cast<float>(u) + 0.5f - cx) / fx * z, (static_cast<float>(v) + 0.5f - cy) / fy * z, z);
    }
  }
  return out;
}

VoxelObstacleLayer::VoxelObstacleLayer(const OccupancyGrid& geometry, const VoxelObstacleLayerOptions& options)
    : geometry_(geometry.width(), geometry.height(), geometry.resolution(), geometry.origin(), OccupancyGrid::kFree),
      o_(options),
      columns_(static_cast<size_t>(geometry.width()) * geometry.height(), 0),
      marked_at_(columns_.size(), 0.0) {
  if (o_.slices < 1 || o_.slices > 32 || !(o_.slice > 0.0))
    throw Error(ErrorCode::kInvalidArgument, "voxel layer: slices must be 1 to 32 and slice > 0 m");
}

void VoxelObstacleLayer::Update(const DepthView& view, const std::vector<Eigen::Vector3d>& hits, double now) {
  // Clearing: each marked slice looked at through the pixel its centre falls in. The ray through
  // that centre leaves the slice's box at some depth; a return at least that far (less the
  // noise: three standard deviations) says the ray crossed the whole box.
  const Eigen::Isometry3d optical_from_map = view.map_from_optical.inverse();
  const Eigen::Vector3d camera = view.map_from_optical.translation();
  const double half = 0.5 * geometry_.resolution();
  const PinholeIntrinsics& k = view.intrinsics;
  bool cleared = false;
  for (const size_t flat : marked_) {
    uint32_t& column = columns_[flat];
    const CellIndex cell{static_cast<int>(flat % geometry_.width()), static_cast<int>(flat / geometry_.width())};
    const Point2 centre = geometry_.CellCenter(cell);
    for (int s = 0; s < o_.slices; ++s) {
      if (!(column & (1u << s))) continue;
      const Eigen::Vector3d c(centre.x(), centre.y(), (s + 0.5) * o_.slice);
      const Eigen::Vector3d p = optical_from_map * c;
      if (!(p.z() > 1e-6) || p.z() < view.range_min || p.z() > view.range_max) continue;
      const double u = std::floor(k.fx * p.x() / p.z() + k.cx), v = std::floor(k.fy * p.y() / p.z() + k.cy);
      if (!(u >= 0 && v >= 0 && u < view.width && v < view.height)) continue;
      const float seen = view.depth[static_cast<size_t>(v) * view.width + static_cast<size_t>(u)];
      if (!std::isfinite(seen)) continue;
      // Depth (along the optical axis) per metre of the map-frame ray through the centre, and
      // where that ray leaves the box.
      const Eigen::Vector3d dir = (c - camera) / p.z();  // map frame, per unit of optical depth
      double leave = std::numeric_limits<double>::infinity();
      const Eigen::Vector3d lo(centre.x() - half, centre.y() - half, s * o_.slice);
      const Eigen::Vector3d hi(centre.x() + half, centre.y() + half, (s + 1) * o_.slice);
      for (int a = 0; a < 3; ++a) {
        if (std::abs(dir[a]) < 1e-12) continue;
        leave = std::min(leave, ((dir[a] > 0 ? hi[a] : lo[a]) - camera[a]) / dir[a]);
      }
      if (seen >= leave - 3.0 * view.noise * leave * leave) {
        column &= ~(1u << s);
        cleared = true;
      }
    }
  }
  if (cleared) {
    ++version_;
    Compact();
  }
  // Marking.
  for (const Eigen::Vector3d& p : hits) {
    const CellIndex c = geometry_.CellOf(p.head<2>());
    if (!geometry_.Contains(c) || p.z() < 0.0) continue;
    const int s = static_cast<int>(p.z() / o_.slice);
    if (s >= o_.slices) continue;
    uint32_t& column = columns_[Flat(c)];
    if (column == 0) marked_.push_back(Flat(c));
    if (!(column & (1u << s))) ++version_;
    column |= 1u << s;
    marked_at_[Flat(c)] = now;
  }
}

void VoxelObstacleLayer::Decay(double now) {
  bool dropped = false;
  for (const size_t flat : marked_) {
    // A clock that went back (a simulator restarted) leaves no mark for ever.
    const double age = now - marked_at_[flat];
    if (age > o_.decay || age < 0.0) {
      columns_[flat] = 0;
      dropped = true;
    }
  }
  if (dropped) {
    ++version_;
    Compact();
  }
}

void VoxelObstacleLayer::Compact() {
  std::erase_if(marked_, [this](size_t flat) { return columns_[flat] == 0; });
}

std::vector<Point2> VoxelObstacleLayer::Obstacles() const {
  std::vector<Point2> out;
  out.reserve(marked_.size());
  for (const size_t flat : marked_)
    out.push_back(
        geometry_.CellCenter({static_cast<int>(flat % geometry_.width()), static_cast<int>(flat / geometry_.width())}));
  return out;
}

}  // namespace navd::perception
