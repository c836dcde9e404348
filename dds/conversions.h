#pragma once
// Conversions between ROS 2 DDS message types and navd's plain types.
#include "builtin_interfaces.h"
#include "geometry_msgs.h"
#include "services/common/pose2.h"

namespace navd::dds {

inline builtin_interfaces::msg::dds_::Time_ ToTime(double seconds) {
  builtin_interfaces::msg::dds_::Time_ t;
  const double s = std::floor(seconds);
  t.sec(static_cast<int32_t>(s));
  t.nanosec(static_cast<uint32_t>(std::min(999'999'999.0, std::round((seconds - s) * 1e9))));
  return t;
}

inline double FromTime(const builtin_interfaces::msg::dds_::Time_& t) { return t.sec() + t.nanosec() * 1e-9; }

inline geometry_msgs::msg::dds_::Pose_ ToPose(const Pose2& p) {
  geometry_msgs::msg::dds_::Pose_ m;
  m.position().x(p.x);
  m.position().y(p.y);
  m.orientation().z(std::sin(p.theta / 2));
  m.orientation().w(std::cos(p.theta / 2));
  return m;
}

inline Pose2 FromPose(const geometry_msgs::msg::dds_::Pose_& m) {
  const auto& q = m.orientation();
  const double yaw = std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()), 1.0 - 2.0 * (q.y() * q.y() + q.z() * q.z()));
  return {m.position().x(), m.position().y(), yaw};
}

}  // namespace navd::dds
