#pragma once
// Conversions between ROS 2 DDS message types and navd's plain types.
#include <Eigen/Core>
#include <array>
#include <string>

#include "builtin_interfaces.h"
#include "geometry_msgs.h"
#include "nav_msgs.h"
#include "services/common/pose2.h"
#include "std_msgs.h"

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

inline std_msgs::msg::dds_::Header_ MakeHeader(double seconds, const std::string& frame) {
  std_msgs::msg::dds_::Header_ h;
  h.stamp(ToTime(seconds));
  h.frame_id(frame);
  return h;
}

// ROS's 6x6 pose covariance (x, y, z, roll, pitch, yaw) and our 3x3 (x, y, theta): indices 0, 1, 5.
inline constexpr int kCovarianceIndex[3] = {0, 1, 5};

inline std::array<double, 36> ToCovariance6(const Eigen::Matrix3d& c) {
  std::array<double, 36> out{};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) out[kCovarianceIndex[r] * 6 + kCovarianceIndex[k]] = c(r, k);
  return out;
}

inline Eigen::Matrix3d FromCovariance6(const std::array<double, 36>& c) {
  Eigen::Matrix3d out;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) out(r, k) = c[kCovarianceIndex[r] * 6 + kCovarianceIndex[k]];
  return out;
}

// nav_msgs/Odometry of a planar pose and body twist (vx forward, vy left, omega), child base_link.
inline nav_msgs::msg::dds_::Odometry_ MakeOdometry(double seconds, const Pose2& pose, double vx, double vy,
                                                   double omega, const Eigen::Matrix3d& covariance,
                                                   const std::string& frame) {
  nav_msgs::msg::dds_::Odometry_ m;
  m.header(MakeHeader(seconds, frame));
  m.child_frame_id("base_link");
  m.pose().pose(ToPose(pose));
  m.pose().covariance(ToCovariance6(covariance));
  m.twist().twist().linear().x(vx);
  m.twist().twist().linear().y(vy);
  m.twist().twist().angular().z(omega);
  return m;
}

}  // namespace navd::dds
