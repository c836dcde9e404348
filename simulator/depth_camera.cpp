#include "simulator/depth_camera.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <cmath>
#include <limits>
#include <memory>

#include "services/common/camera_frame.h"
#include "services/common/ziggurat_normal.h"
#include "simulator/laser_scanner.h"

namespace navd::sim {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Depth (ray parameter) where a ray from the origin enters a box whose corners, relative to the
// origin, are lo and hi; `inverse` is 1 / the ray's direction per axis (infinite along an axis it
// does not move on, where the product tells inside (NaN never wins a min/max) from outside).
float RayBox(const Eigen::Array3f& lo, const Eigen::Array3f& hi, const Eigen::Array3f& inverse) {
  const Eigen::Array3f a = lo * inverse, b = hi * inverse;
  const Eigen::Array3f near = a.min(b), far = a.max(b);
  const float enter = std::max({0.0f, near.x(), near.y(), near.z()});
  const float leave = std::min({far.x(), far.y(), far.z()});
  return enter <= leave && enter > 0.0f ? enter : kInfinity;
}

}  // namespace

DepthCamera::DepthCamera(const DepthCameraDescription& description)
    : d_(description), intrinsics_(IntrinsicsOf(description)), to_robot_(RobotFromOptical(description).linear()) {
  const auto [fx, fy, cx, cy] = intrinsics_;
  for (int u = 0; u < d_.width; ++u) column_x_.push_back(static_cast<float>((u + 0.5 - cx) / fx));
  for (int v = 0; v < d_.height; ++v) row_y_.push_back(static_cast<float>((v + 0.5 - cy) / fy));
  // Slivers as wide as a pixel at the image's centre, so a wall is sampled as finely as the image
  // samples it; at most 65,535 round the circle, as their indices are 16 bits.
  sliver_width_ = std::max(d_.hfov / d_.width, 2.0 * M_PI / 65535.0);
  const int slivers = static_cast<int>(std::ceil(2.0 * M_PI / sliver_width_));
  std::vector<float> reach(static_cast<size_t>(slivers), 0.0f);
  const size_t count = static_cast<size_t>(d_.width) * d_.height;
  sliver_.reserve(count);
  for (int v = 0; v < d_.height; ++v) {
    for (int u = 0; u < d_.width; ++u) {
      const Eigen::Vector3f robot = to_robot_ * Eigen::Vector3f(column_x_[u], row_y_[v], 1.0f);
      const float horizontal = std::hypot(robot.x(), robot.y());
      const float floor = robot.z() < 0.0f ? static_cast<float>(d_.mount_z / -robot.z()) : kInfinity;
      const double bearing = std::atan2(robot.y(), robot.x());
      const int sliver = std::clamp(static_cast<int>(std::floor((bearing + M_PI) / sliver_width_)), 0, slivers - 1);
      sliver_.push_back(static_cast<uint16_t>(sliver));
      // How far across the floor this pixel can see a wall: to its range, or to the floor.
      float& r = reach[static_cast<size_t>(sliver)];
      r = std::max(r, std::min(static_cast<float>(d_.range_max), floor) * horizontal);
    }
  }
  for (int b = 0; b < slivers; ++b) {
    const float r = reach[static_cast<size_t>(b)];
    if (r <= 0.0f) continue;
    const double bearing = -M_PI + (b + 0.5) * sliver_width_;
    casts_.push_back({static_cast<uint16_t>(b), Point2(std::cos(bearing), std::sin(bearing)), r});
    max_reach_ = std::max(max_reach_, static_cast<double>(r));
  }
  slivers_ = slivers;
  // Per pixel, fixed by the mount: metres of depth per metre across the floor (a wall's depth is
  // its distance across the floor times this), and the depth at which the ray meets the floor.
  per_across_.reserve(count);
  floor_depth_.reserve(count);
  const auto mount_z = static_cast<float>(d_.mount_z);
  const Eigen::Matrix3f& r = to_robot_;
  for (size_t v = 0; v < static_cast<size_t>(d_.height); ++v) {
    const Eigen::Vector3f row = r.col(1) * row_y_[v] + r.col(2);
    for (size_t u = 0; u < static_cast<size_t>(d_.width); ++u) {
      const float x = column_x_[u];
      const float ahead = row.x() + r(0, 0) * x, left = row.y() + r(1, 0) * x, up = row.z() + r(2, 0) * x;
      per_across_.push_back(1.0f / std::sqrt(ahead * ahead + left * left));
      floor_depth_.push_back(mount_z / (-up > 1e-6f ? -up : 1e-6f));  // beyond any range when the ray looks up
    }
  }
  // The noise table, depth noise per square metre of depth: longer than an image, so a frame's
  // pattern starts anywhere in it; its own stream, so the camera's description alone decides it.
  std::mt19937_64 rng(0x6e617664);
  noise_.resize(2 * count + 4099);
  for (float& n : noise_) {
    const bool hole = d_.holes > 0.0 && static_cast<double>(rng() >> 11) * 0x1.0p-53 < d_.holes;
    n = hole ? kNaN : static_cast<float>(d_.noise * ZigguratNormal::Standard(rng));
  }
}

DepthCamera::PixelRect DepthCamera::CoverOf(const Eigen::Matrix3f& to_optical, const Eigen::Vector3f& lo,
                                            const Eigen::Vector3f& hi) const {
  // The box cut a millimetre in front of the camera: its corners beyond, and where its edges cross
  // that plane. Their images bound the image of all of the box in front of the camera.
  std::array<Eigen::Vector3f, 8> corner;
  for (int k = 0; k < 8; ++k)
    corner[k] =
        to_optical * Eigen::Vector3f((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
  // A millimetre, not range_min: a box crossed nearer than range_min still hides what is behind it.
  constexpr float near = 1e-3f;
  PixelRect r{d_.width, -1, d_.height, -1};
  auto include = [&](const Eigen::Vector3f& q) {
    const double u = intrinsics_.fx * q.x() / q.z() + intrinsics_.cx;
    const double v = intrinsics_.fy * q.y() / q.z() + intrinsics_.cy;
    // A pixel's margin either side for rounding; the clamp keeps far-off corners finite.
    const int pu = static_cast<int>(std::floor(std::clamp(u, -2.0, d_.width + 2.0)));
    const int pv = static_cast<int>(std::floor(std::clamp(v, -2.0, d_.height + 2.0)));
    r.u0 = std::min(r.u0, pu - 1);
    r.u1 = std::max(r.u1, pu + 1);
    r.v0 = std::min(r.v0, pv - 1);
    r.v1 = std::max(r.v1, pv + 1);
  };
  for (int k = 0; k < 8; ++k) {
    if (corner[k].z() >= near) include(corner[k]);
    for (int axis = 1; axis < 8; axis <<= 1) {  // the edges to corners with one more coordinate at hi
      if (k & axis) continue;
      const Eigen::Vector3f& a = corner[k];
      const Eigen::Vector3f& b = corner[k | axis];
      if ((a.z() < near) != (b.z() < near)) include(a + (b - a) * ((near - a.z()) / (b.z() - a.z())));
    }
  }
  r.u0 = std::max(r.u0, 0);
  r.v0 = std::max(r.v0, 0);
  r.u1 = std::min(r.u1, d_.width - 1);
  r.v1 = std::min(r.v1, d_.height - 1);
  return r;
}

std::vector<Eigen::Vector3f> DepthCamera::Capture(const Pose2& pose, const RayCaster& walls,
                                                  const std::vector<Solid>& solids, const std::vector<Disc>& discs,
                                                  int self, std::mt19937_64& rng) const {
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  const Point2 origin = pose * Point2(d_.mount_x, d_.mount_y);
  // Optical directions to the map frame's axes, and back.
  Eigen::Matrix3f to_map = to_robot_;
  to_map.row(0) = static_cast<float>(c) * to_robot_.row(0) - static_cast<float>(s) * to_robot_.row(1);
  to_map.row(1) = static_cast<float>(s) * to_robot_.row(0) + static_cast<float>(c) * to_robot_.row(1);
  const Eigen::Matrix3f to_optical = to_map.transpose();
  // Walls, metres across the floor per bearing sliver: a cast on every other sliver; one between
  // two casts that meet the same surface (within kSameSurface of each other) takes their mean,
  // which a flat wall's depth matches to a millimetre at these angles; any other gets its own cast.
  constexpr double kSameSurface = 0.05;  // m
  const double cell = walls.grid().resolution();
  std::vector<float> wall(static_cast<size_t>(slivers_), kInfinity);
  std::vector<double> cast_range(casts_.size(), 0.0);
  auto cast_at = [&](size_t k) {
    const Cast& cast = casts_[k];
    const Point2 dir(c * cast.dir.x() - s * cast.dir.y(), s * cast.dir.x() + c * cast.dir.y());
    cast_range[k] = walls.CastOpenEdge(origin, dir, cast.reach);
  };
  for (size_t k = 0; k < casts_.size(); k += 2) cast_at(k);
  for (size_t k = 1; k < casts_.size(); k += 2) {
    if (k + 1 == casts_.size() || casts_[k + 1].sliver != casts_[k - 1].sliver + 2) {
      cast_at(k);
      continue;
    }
    const Cast &before = casts_[k - 1], &after = casts_[k + 1];
    const double a = cast_range[k - 1], b = cast_range[k + 1];
    // Neither meets a wall, and both look at least as far as this one would.
    const bool open = a >= before.reach && b >= after.reach && casts_[k].reach <= std::min(before.reach, after.reach);
    const bool same = a < before.reach && b < after.reach && std::abs(a - b) <= kSameSurface;
    // Only where the two casts are closer together than a map cell is wide (within 3.5 m at 5 cm
    // and the default image), so no cell fits between them unseen.
    const double apart = 2.0 * sliver_width_ * (open ? casts_[k].reach : std::max(a, b));
    if ((open || same) && apart <= cell)
      cast_range[k] = open ? casts_[k].reach : 0.5 * (a + b);
    else
      cast_at(k);
  }
  for (size_t k = 0; k < casts_.size(); ++k)
    if (cast_range[k] < casts_[k].reach) wall[casts_[k].sliver] = static_cast<float>(cast_range[k]);
  // Solids and bodies: each tests only the pixels its image can cover, keeping the nearest depth
  // per pixel in `nearer`; rows none of them covers read a row of infinities instead.
  const Eigen::Vector3f camera(static_cast<float>(origin.x()), static_cast<float>(origin.y()),
                               static_cast<float>(d_.mount_z));
  struct Box {
    Eigen::Vector3f lo, hi;  // corners relative to the camera, map axes
    PixelRect cover;
    const Disc* disc;  // a body's upright cylinder within the box, or null for a solid box
  };
  std::vector<Box> boxes;
  for (const Solid& solid : solids) {
    const Point2 closest(std::clamp(origin.x(), solid.box.min.x(), solid.box.max.x()),
                         std::clamp(origin.y(), solid.box.min.y(), solid.box.max.y()));
    if (Distance(closest, origin) > max_reach_) continue;
    const Eigen::Vector3f lo =
        Eigen::Vector3d(solid.box.min.x(), solid.box.min.y(), solid.z_min).cast<float>() - camera;
    const Eigen::Vector3f hi =
        Eigen::Vector3d(solid.box.max.x(), solid.box.max.y(), solid.z_max).cast<float>() - camera;
    boxes.push_back({lo, hi, CoverOf(to_optical, lo, hi), nullptr});
  }
  for (const Disc* disc : DiscsWithin(discs, origin, max_reach_, self)) {
    if (Distance(disc->centre, origin) <= disc->radius) continue;  // the camera is inside it: it sees nothing of it
    const Eigen::Vector3f lo =
        Eigen::Vector3d(disc->centre.x() - disc->radius, disc->centre.y() - disc->radius, 0.0).cast<float>() - camera;
    const Eigen::Vector3f hi =
        Eigen::Vector3d(disc->centre.x() + disc->radius, disc->centre.y() + disc->radius, kBodyHeight).cast<float>() -
        camera;
    boxes.push_back({lo, hi, CoverOf(to_optical, lo, hi), disc});
  }
  const size_t pixels = sliver_.size();
  const auto width = static_cast<size_t>(d_.width);
  const std::vector<float> open_row(width, kInfinity);
  std::vector<const float*> nearer_row(static_cast<size_t>(d_.height), open_row.data());
  const std::unique_ptr<float[]> nearer(new float[pixels]);  // NOLINT(modernize-avoid-c-arrays): filled per row used
  for (const Box& box : boxes) {
    for (int v = box.cover.v0; v <= box.cover.v1; ++v) {
      float* row = nearer.get() + static_cast<size_t>(v) * width;
      if (nearer_row[static_cast<size_t>(v)] != row) std::fill(row, row + width, kInfinity);
      nearer_row[static_cast<size_t>(v)] = row;
    }
  }
  for (const Box& box : boxes) {
    const PixelRect& r = box.cover;
    for (int v = r.v0; v <= r.v1; ++v) {
      // The map-frame ray per metre of depth of pixel (u, v): row + to_map.col(0) * column_x_[u].
      const Eigen::Vector3f row = to_map.col(1) * row_y_[static_cast<size_t>(v)] + to_map.col(2);
      for (int u = r.u0; u <= r.u1; ++u) {
        const size_t i = static_cast<size_t>(v) * width + static_cast<size_t>(u);
        const Eigen::Vector3f ray = row + to_map.col(0) * column_x_[static_cast<size_t>(u)];
        float& d = nearer[i];
        if (!box.disc) {
          d = std::min(d, RayBox(box.lo.array(), box.hi.array(), ray.array().inverse()));
          continue;
        }
        const float horizontal = std::hypot(ray.x(), ray.y());
        if (horizontal <= 1e-6f) continue;
        const float per_across = 1.0f / horizontal;
        const Point2 flat = Point2(ray.x(), ray.y()) * per_across;
        const double along = RayDiscDistance(origin, flat, *box.disc) * per_across;
        const double z = d_.mount_z + along * ray.z();
        if (std::isfinite(along) && z >= 0.0 && z <= kBodyHeight) d = std::min(d, static_cast<float>(along));
      }
    }
  }
  // The nearest of floor, wall and the rest; holes, range limits and noise; then the points. Row
  // by row in three passes: the walls' depths gathered, then depths and noise for the whole row
  // at once (a loop the compiler vectorizes; NaN marks no reading), then the points kept.
  const size_t noise_at = static_cast<size_t>(rng() % (noise_.size() - pixels));
  const auto range_min = static_cast<float>(d_.range_min), range_max = static_cast<float>(d_.range_max);
  // Two spare points: each point is stored as four floats at once (one store, not two), the fourth
  // overwritten by the next point or left in the spare room.
  std::vector<Eigen::Vector3f> points(pixels + 2);
  std::vector<float> across(width), seen(width);
  static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float));
  auto* out = reinterpret_cast<float*>(points.data());  // NOLINT(*-reinterpret-cast): three packed floats each
  size_t count = 0;
  for (size_t v = 0; v < static_cast<size_t>(d_.height); ++v) {
    const size_t first = v * width;
    const uint16_t* sliver = sliver_.data() + first;
    for (size_t u = 0; u < width; ++u) across[u] = wall[sliver[u]];
    const float* per_across = per_across_.data() + first;
    const float* floor = floor_depth_.data() + first;
    const float* noise = noise_.data() + noise_at + first;
    const float* near = nearer_row[v];
    for (size_t u = 0; u < width; ++u) {
      const float wall_depth = across[u] * per_across[u];
      const float nearest = wall_depth < floor[u] ? wall_depth : floor[u];
      const float truth = near[u] < nearest ? near[u] : nearest;
      const float z = truth + truth * truth * noise[u];
      seen[u] = (truth >= range_min) & (truth <= range_max) ? z : kNaN;
    }
    const float y = row_y_[v];
    for (size_t u = 0; u < width; ++u) {
      const float z = seen[u];
      // Written always, kept only when read: holes fall at random, and a branch on them would be
      // mispredicted at every one.
      const std::array<float, 4> point{column_x_[u] * z, y * z, z, 0.0f};
      std::memcpy(out + 3 * count, point.data(), sizeof(point));
      count += static_cast<size_t>(z == z);
    }
  }
  points.resize(count);
  return points;
}

}  // namespace navd::sim
