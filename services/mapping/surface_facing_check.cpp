#include "services/mapping/surface_facing_check.h"

#include <cmath>
#include <cstddef>

namespace navd::mapping {

namespace {

constexpr int64_t kRow = int64_t{1} << 32;  // cells per row of the key space
constexpr double kPi = 3.14159265358979323846;

}  // namespace

int SurfaceFacingCheck::Sector(const Point2& normal) {
  const double a = std::atan2(normal.y(), normal.x());  // -pi..pi
  return static_cast<int>(std::floor((a + kPi) / (2.0 * kPi) * kSectors)) % kSectors;
}

SurfaceFacingCheck::SurfaceFacingCheck(const std::vector<PlacedReturns>& reference, const SurfaceFacingOptions& options)
    : o_(options) {
  for (const PlacedReturns& r : reference) {
    if (!r.points) continue;
    const std::vector<Point2> normals = Normals(*r.points);
    for (size_t i = 0; i < normals.size(); ++i) {
      if (normals[i].isZero()) continue;
      facings_[Key(r.pose * (*r.points)[i])] |= static_cast<uint8_t>(1u << Sector(Rotate(normals[i], r.pose.theta)));
    }
  }
}
std::vector<Point2> SurfaceFacingCheck::Normals(const std::vector<Point2>& points) const {
  std::vector<Point2> out(points.size(), Point2::Zero());
  const size_t span = static_cast<size_t>(o_.span);
  for (size_t i = span; i + span < points.size(); ++i) {
    const Point2& p = points[i];
    const Point2& a = points[i - span];
    const Point2& b = points[i + span];
    if ((a - p).norm() > o_.max_reach || (b - p).norm() > o_.max_reach) continue;
    const Point2 along = b - a;
    const double length = along.norm();
    if (length <= 0.0) continue;
    Point2 normal(-along.y() / length, along.x() / length);
    if (std::abs(normal.dot(p - a)) > o_.max_offset) continue;  // a corner or clutter, not a wall
    if (normal.dot(-p) < 0.0) normal = -normal;                 // towards the sensor (the origin)
    out[i] = normal;
  }
  return out;
}

int64_t SurfaceFacingCheck::Key(const Point2& p) const {
  const auto x = static_cast<int64_t>(std::floor(p.x() / o_.resolution));
  const auto y = static_cast<int64_t>(std::floor(p.y() / o_.resolution));
  return y * kRow + x;
}

double SurfaceFacingCheck::BehindShare(const Pose2& pose, const std::vector<Point2>& scan) const {
  const std::vector<Point2> normals = Normals(scan);
  int on_walls = 0, behind = 0;
  for (size_t i = 0; i < scan.size(); ++i) {
    if (normals[i].isZero()) continue;
    const int64_t key = Key(pose * scan[i]);
    uint8_t reference = 0;
    for (int64_t dy = -1; dy <= 1; ++dy) {
      for (int64_t dx = -1; dx <= 1; ++dx) {
        const auto it = facings_.find(key + dy * kRow + dx);
        if (it != facings_.end()) reference |= it->second;
      }
    }
    if (reference == 0) continue;
    ++on_walls;
    // The sectors within a right angle of this return's facing, either way.
    const int sector = Sector(Rotate(normals[i], pose.theta));
    uint8_t facing_alike = 0;
    for (int d = -kSectors / 4; d <= kSectors / 4; ++d)
      facing_alike |= static_cast<uint8_t>(1u << ((sector + d + kSectors) % kSectors));
    if ((reference & facing_alike) == 0) ++behind;
  }
  return on_walls > 0 ? static_cast<double>(behind) / on_walls : 0.0;
}

}  // namespace navd::mapping
