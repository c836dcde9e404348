#pragma once
// sensor_msgs/PointCloud2 as ROS 2 lays it out: points of `point_step` bytes in rows of
// `row_step`, each field (name, byte offset, datatype, count) found by name. navsim writes xyz
// clouds; navd reads any cloud with x, y and z fields of FLOAT32 or FLOAT64, either byte order,
// organized (height > 1, NaN for pixels without a reading) or not, as ROS drivers publish them.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "sensor_msgs.h"

namespace navd::dds {

// ROS 2's sensor_msgs/PointField datatypes.
enum PointFieldType : uint8_t {
  kInt8 = 1,
  kUInt8 = 2,
  kInt16 = 3,
  kUInt16 = 4,
  kInt32 = 5,
  kUInt32 = 6,
  kFloat32 = 7,
  kFloat64 = 8
};

// An unorganized cloud (height 1) of x, y, z FLOAT32 fields, 12 bytes a point, host byte order.
sensor_msgs::msg::dds_::PointCloud2_ EncodeXyzCloud(const std::vector<Eigen::Vector3f>& points, double stamp,
                                                    const std::string& frame_id);

// The finite points of a cloud, in its header's frame. Throws navd::Error(kInvalidArgument) naming
// the field when the layout is not one the rules allow (no x, y or z field, a field outside the
// point, a datatype that is not a float, data shorter than height * row_step).
std::vector<Eigen::Vector3f> DecodeXyzCloud(const sensor_msgs::msg::dds_::PointCloud2_& cloud);

}  // namespace navd::dds
