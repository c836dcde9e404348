#include "simulator/depth_camera.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "services/common/camera_frame.h"
#include "services/common/ziggurat_normal.h"
#include "simulator/laser_scanner.h"

namespace navd::sim {
namespace {

constexpr double kBinWidth = 0.25 * M_PI / 180.0;  // rad of bearing per wall cast
constexpr int kBins = static_cast<int>(2.0 * M_PI / kBinWidth) + 1;

int BinOf(double bearing) {
  const int b = static_cast<int>(std::floor((bearing + M_PI) / kBinWidth));
  return std::clamp(b, 0, kBins - 1);
}
double BinBearing(int bin) { return -M_PI + (bin + 0.5) * kBinWidth; }

// Depth (ray parameter) where a ray from the origin enters a box whose corners, relative to the
// origin, are lo and hi; `inverse` is 1 / the ray's direction per axis (infinite along an axis it
// does not move on, where the product tells inside (NaN never wins a min/max) from outside).
float RayBox(const Eigen::Array3f& lo, const Eigen::Array3f& hi, const Eigen::Array3f& inverse) {
  const Eigen::Array3f a = lo * inverse, b = hi * inverse;
  const Eigen::Array3f near = a.min(b), far = a.max(b);
  const float enter = std::max({0.0f, near.x(), near.y(), near.z()});
  const float leave = std::min({far.x(), far.y(), far.z()});
  return enter <= leave && enter > 0.0f ? enter : std::numeric_limits<float>::infinity();
}

}  // namespace

DepthCamera::DepthCamera(const DepthCameraDescription& description) : d_(description) {
  const auto [fx, fy, cx, cy] = IntrinsicsOf(d_);
  const Eigen::Matrix3f to_robot = RobotFromOptical(d_).linear();
  std::vector<bool> used(kBins, false);
  double widest = 0.0;
  pixels_.reserve(static_cast<size_t>(d_.width) * d_.height);
  for (int v = 0; v < d_.height; ++v) {
    for (int u = 0; u < d_.width; ++u) {
      Pixel p;
      p.optical =
          Eigen::Vector3f(static_cast<float>((u + 0.5 - cx) / fx), static_cast<float>((v + 0.5 - cy) / fy), 1.0f);
      p.robot = to_robot * p.optical;
      p.horizontal = std::hypot(p.robot.x(), p.robot.y());
      p.per_across = p.horizontal > 1e-6f ? 1.0f / p.horizontal : 0.0f;
      p.floor =
          p.robot.z() < 0.0f ? static_cast<float>(d_.mount_z / -p.robot.z()) : std::numeric_limits<float>::infinity();
      p.bin = BinOf(std::atan2(p.robot.y(), p.robot.x()));
      used[static_cast<size_t>(p.bin)] = true;
      widest = std::max(widest, static_cast<double>(p.horizontal));
      pixels_.push_back(p);
    }
  }
  for (int b = 0; b < kBins; ++b)
    if (used[static_cast<size_t>(b)]) bins_used_.push_back(b);
  max_reach_ = d_.range_max * widest;
  // The noise table: longer than an image, so a frame's pattern starts anywhere in it; its own
  // stream, so the camera's description alone decides it.
  std::mt19937_64 rng(0x6e617664);
  noise_.resize(2 * pixels_.size() + 4099);
  for (float& n : noise_) {
    const bool hole = d_.holes > 0.0 && static_cast<double>(rng() >> 11) * 0x1.0p-53 < d_.holes;
    n = hole ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(ZigguratNormal::Standard(rng));
  }
}

std::vector<Eigen::Vector3f> DepthCamera::Capture(const Pose2& pose, const RayCaster& walls,
                                                  const std::vector<Solid>& solids, const std::vector<Disc>& discs,
                                                  int self, std::mt19937_64& rng) const {
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  const Point2 origin = pose * Point2(d_.mount_x, d_.mount_y);
  // Walls: one cast per bearing sliver, metres across the floor.
  std::vector<float> wall(kBins, std::numeric_limits<float>::infinity());
  for (int b : bins_used_) {
    const double r = walls.CastOpenEdge(origin, pose.theta + BinBearing(b), max_reach_);
    if (r < max_reach_) wall[static_cast<size_t>(b)] = static_cast<float>(r);
  }
  // Slivers (relative to the heading) a footprint seen from the camera spans, all from inside it.
  std::vector<uint8_t> busy(kBins, 0);  // some solid or body spans the sliver
  auto span = [&](const Point2& centre, double half_angle, int& first, int& last) {
    const double bearing = std::atan2(centre.y() - origin.y(), centre.x() - origin.x()) - pose.theta;
    first = std::max(0, BinOf(NormalizeAngle(bearing - half_angle)) - 1);
    last = std::min(kBins - 1, BinOf(NormalizeAngle(bearing + half_angle)) + 1);
    if (first <= last) {
      std::fill(busy.begin() + first, busy.begin() + last + 1, 1);
    } else {  // across the bearing behind the robot
      std::fill(busy.begin() + first, busy.end(), 1);
      std::fill(busy.begin(), busy.begin() + last + 1, 1);
    }
  };
  struct Near {
    Eigen::Array3f lo, hi;  // corners relative to the camera
    int first = 0, last = kBins - 1;
  };
  std::vector<Near> near;
  for (const Solid& solid : solids) {
    const Point2 closest(std::clamp(origin.x(), solid.box.min.x(), solid.box.max.x()),
                         std::clamp(origin.y(), solid.box.min.y(), solid.box.max.y()));
    const double gap = Distance(closest, origin);
    if (gap > max_reach_) continue;
    Near n{Eigen::Array3f(static_cast<float>(solid.box.min.x() - origin.x()),
                          static_cast<float>(solid.box.min.y() - origin.y()),
                          static_cast<float>(solid.z_min - d_.mount_z)),
           Eigen::Array3f(static_cast<float>(solid.box.max.x() - origin.x()),
                          static_cast<float>(solid.box.max.y() - origin.y()),
                          static_cast<float>(solid.z_max - d_.mount_z))};
    const Point2 centre = 0.5 * (solid.box.min + solid.box.max);
    const double half_diagonal = 0.5 * (solid.box.max - solid.box.min).norm();
    const double to_centre = Distance(centre, origin);
    if (to_centre > half_diagonal) {
      span(centre, std::asin(half_diagonal / to_centre), n.first, n.last);
    } else {
      std::fill(busy.begin(), busy.end(), 1);  // the camera is over it
    }
    near.push_back(n);
  }
  // Per sliver, the solids whose bearings span it (a compressed list: the solids of sliver b are
  // sliver_solids[sliver_start[b] .. sliver_start[b + 1]]), so a pixel tests only those.
  std::vector<uint32_t> sliver_start(kBins + 1, 0);
  auto each_sliver = [](const Near& n, auto&& visit) {
    if (n.first <= n.last) {
      for (int b = n.first; b <= n.last; ++b) visit(b);
    } else {
      for (int b = n.first; b < kBins; ++b) visit(b);
      for (int b = 0; b <= n.last; ++b) visit(b);
    }
  };
  for (const Near& n : near) each_sliver(n, [&](int b) { ++sliver_start[static_cast<size_t>(b) + 1]; });
  for (int b = 0; b < kBins; ++b) sliver_start[static_cast<size_t>(b) + 1] += sliver_start[static_cast<size_t>(b)];
  std::vector<uint32_t> sliver_solids(sliver_start[kBins]);
  {
    std::vector<uint32_t> next(sliver_start.begin(), sliver_start.end() - 1);
    for (uint32_t k = 0; k < near.size(); ++k)
      each_sliver(near[k], [&](int b) { sliver_solids[next[static_cast<size_t>(b)]++] = k; });
  }
  struct Body {
    const Disc* disc;
    int first = 0, last = kBins - 1;
    bool In(int bin) const { return first > last ? (bin >= first || bin <= last) : (bin >= first && bin <= last); }
  };
  std::vector<Body> bodies;
  for (const Disc* disc : DiscsWithin(discs, origin, max_reach_, self)) {
    Body b{disc};
    const double to_centre = Distance(disc->centre, origin);
    if (to_centre <= disc->radius) continue;  // the camera is inside it: it sees nothing of it
    span(disc->centre, std::asin(disc->radius / to_centre), b.first, b.last);
    bodies.push_back(b);
  }
  const size_t noise_at = static_cast<size_t>(rng() % (noise_.size() - pixels_.size()));
  std::vector<Eigen::Vector3f> points(pixels_.size());
  size_t count = 0;
  for (size_t i = 0; i < pixels_.size(); ++i) {
    const Pixel& p = pixels_[i];
    const float noise = noise_[noise_at + i];
    if (std::isnan(noise)) continue;  // a hole
    double depth = std::min(p.floor, wall[static_cast<size_t>(p.bin)] * p.per_across);
    if (busy[static_cast<size_t>(p.bin)]) {
      const Eigen::Vector3d dir(c * p.robot.x() - s * p.robot.y(), s * p.robot.x() + c * p.robot.y(), p.robot.z());
      const Eigen::Array3f inverse = dir.cast<float>().array().inverse();
      const auto bin = static_cast<size_t>(p.bin);
      for (uint32_t k = sliver_start[bin]; k < sliver_start[bin + 1]; ++k) {
        const Near& n = near[sliver_solids[k]];
        depth = std::min(depth, static_cast<double>(RayBox(n.lo, n.hi, inverse)));
      }
      if (p.horizontal > 1e-6f) {
        const Point2 flat = Point2(dir.x(), dir.y()) * p.per_across;
        for (const Body& b : bodies) {
          if (!b.In(p.bin)) continue;
          const double at = RayDiscDistance(origin, flat, *b.disc) * p.per_across;
          const double z = d_.mount_z + at * dir.z();
          if (std::isfinite(at) && z >= 0.0 && z <= kBodyHeight) depth = std::min(depth, at);
        }
      }
    }
    if (depth < d_.range_min || depth > d_.range_max) continue;
    depth += d_.noise * depth * depth * noise;
    points[count++] = p.optical * static_cast<float>(depth);
  }
  points.resize(count);
  return points;
}

}  // namespace navd::sim
