#include "dds/point_cloud2.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "dds/conversions.h"
#include "services/common/error.h"

namespace navd::dds {
namespace {

constexpr bool kHostBigEndian = std::endian::native == std::endian::big;

struct FieldReader {
  uint32_t offset = 0;
  uint8_t datatype = 0;
};

FieldReader FindField(const sensor_msgs::msg::dds_::PointCloud2_& cloud, const char* name) {
  for (size_t i = 0; i < cloud.fields().size(); ++i) {
    const auto& f = cloud.fields()[i];
    if (f.name() != name) continue;
    const std::string field = "fields[" + std::to_string(i) + "] (" + name + ")";
    if (f.datatype() != kFloat32 && f.datatype() != kFloat64)
      throw Error(ErrorCode::kInvalidArgument,
                  field + ".datatype " + std::to_string(f.datatype()) + " is not FLOAT32 (7) or FLOAT64 (8)");
    const uint32_t size = f.datatype() == kFloat32 ? 4 : 8;
    if (f.count() < 1) throw Error(ErrorCode::kInvalidArgument, field + ".count must be at least 1");
    if (static_cast<uint64_t>(f.offset()) + size > cloud.point_step())
      throw Error(ErrorCode::kInvalidArgument, field + ".offset " + std::to_string(f.offset()) +
                                                   " puts it past the point's point_step of " +
                                                   std::to_string(cloud.point_step()) + " bytes");
    return {f.offset(), f.datatype()};
  }
  throw Error(ErrorCode::kInvalidArgument, std::string("fields has no '") + name + "' field");
}

double Read(const uint8_t* at, uint8_t datatype, bool swap) {
  uint8_t bytes[8];
  const size_t size = datatype == kFloat32 ? 4 : 8;
  std::memcpy(bytes, at, size);
  if (swap) std::reverse(bytes, bytes + size);
  if (datatype == kFloat32) {
    float f = 0.0f;
    std::memcpy(&f, bytes, 4);
    return f;
  }
  double d = 0.0;
  std::memcpy(&d, bytes, 8);
  return d;
}

}  // namespace

sensor_msgs::msg::dds_::PointCloud2_ EncodeXyzCloud(const std::vector<Eigen::Vector3f>& points, double stamp,
                                                    const std::string& frame_id) {
  sensor_msgs::msg::dds_::PointCloud2_ m;
  m.header(MakeHeader(stamp, frame_id));
  m.height(1);
  m.width(static_cast<uint32_t>(points.size()));
  const char* names[] = {"x", "y", "z"};
  for (uint32_t k = 0; k < 3; ++k) {
    sensor_msgs::msg::dds_::PointField_ f;
    f.name(names[k]);
    f.offset(4 * k);
    f.datatype(kFloat32);
    f.count(1);
    m.fields().push_back(f);
  }
  m.is_bigendian(kHostBigEndian);
  m.point_step(12);
  m.row_step(12 * static_cast<uint32_t>(points.size()));
  m.data().resize(12 * points.size());
  for (size_t i = 0; i < points.size(); ++i) std::memcpy(m.data().data() + 12 * i, points[i].data(), 12);
  m.is_dense(true);
  return m;
}

std::vector<Eigen::Vector3f> DecodeXyzCloud(const sensor_msgs::msg::dds_::PointCloud2_& cloud) {
  const FieldReader x = FindField(cloud, "x"), y = FindField(cloud, "y"), z = FindField(cloud, "z");
  const uint64_t row_bytes = static_cast<uint64_t>(cloud.width()) * cloud.point_step();
  if (cloud.row_step() < row_bytes)
    throw Error(ErrorCode::kInvalidArgument, "row_step " + std::to_string(cloud.row_step()) +
                                                 " is under width * point_step (" + std::to_string(row_bytes) + ")");
  const uint64_t need = static_cast<uint64_t>(cloud.height()) * cloud.row_step();
  if (cloud.data().size() < need)
    throw Error(ErrorCode::kInvalidArgument, "data holds " + std::to_string(cloud.data().size()) +
                                                 " bytes, under height * row_step (" + std::to_string(need) + ")");
  const bool swap = cloud.is_bigendian() != kHostBigEndian;
  std::vector<Eigen::Vector3f> points;
  points.reserve(static_cast<size_t>(cloud.height()) * cloud.width());
  for (uint32_t row = 0; row < cloud.height(); ++row) {
    const uint8_t* line = cloud.data().data() + static_cast<size_t>(row) * cloud.row_step();
    for (uint32_t col = 0; col < cloud.width(); ++col) {
      const uint8_t* p = line + static_cast<size_t>(col) * cloud.point_step();
      const double px = Read(p + x.offset, x.datatype, swap), py = Read(p + y.offset, y.datatype, swap),
                   pz = Read(p + z.offset, z.datatype, swap);
      if (std::isfinite(px) && std::isfinite(py) && std::isfinite(pz))
        points.emplace_back(static_cast<float>(px), static_cast<float>(py), static_cast<float>(pz));
    }
  }
  return points;
}

}  // namespace navd::dds
