#pragma once
// Where a depth camera's points are on the robot: its optical frame (ROS REP 103: x right, y down,
// z along the optical axis) to the robot frame (x ahead, y left, z up from the floor), by the
// mount and tilt of DepthCameraDescription. Shared by navsim's camera and navd's perception, so
// both place a pixel alike. Metres.
#include <Eigen/Geometry>
#include <cmath>

#include "services/common/world.h"

namespace navd {

// The pinhole model of the description's image: pixel (u, v) (u right, v down, from the top
// left corner) sees along optical direction ((u + 0.5 - cx) / fx, (v + 0.5 - cy) / fy, 1).
struct PinholeIntrinsics {
  double fx = 1.0, fy = 1.0, cx = 0.0, cy = 0.0;
};

inline PinholeIntrinsics IntrinsicsOf(const DepthCameraDescription& d) {
  return {0.5 * d.width / std::tan(0.5 * d.hfov), 0.5 * d.height / std::tan(0.5 * d.vfov), 0.5 * d.width,
          0.5 * d.height};
}

inline Eigen::Isometry3f RobotFromOptical(const DepthCameraDescription& d) {
  // Optical axes in a level camera's frame, then the camera pitched down by the tilt.
  Eigen::Matrix3f optical_to_level;
  optical_to_level << 0, 0, 1,  //
      -1, 0, 0,                 //
      0, -1, 0;
  const Eigen::Matrix3f tilt =
      Eigen::AngleAxisf(static_cast<float>(d.tilt), Eigen::Vector3f::UnitY()).toRotationMatrix();
  Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
  t.linear() = tilt * optical_to_level;
  t.translation() =
      Eigen::Vector3f(static_cast<float>(d.mount_x), static_cast<float>(d.mount_y), static_cast<float>(d.mount_z));
  return t;
}

}  // namespace navd
