#include "services/localization/odometry_localizer.h"

#include <Eigen/Geometry>

namespace navd::localization {

OdometryLocalizer::OdometryLocalizer(const Pose2& initial_pose) : initial_pose_(initial_pose) {}

void OdometryLocalizer::AddOdometry(const OdometryReading& reading) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!have_reading_) {
    map_from_odom_ = initial_pose_ * reading.pose.inverse();
    odom_covariance_at_anchor_ = reading.covariance;
    have_reading_ = true;
  }
  last_ = reading;
}

void OdometryLocalizer::ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!have_reading_) {
    initial_pose_ = pose;
  } else {
    map_from_odom_ = pose * last_.pose.inverse();
    odom_covariance_at_anchor_ = last_.covariance;
  }
  anchor_covariance_ = covariance;
}

PoseEstimate OdometryLocalizer::Estimate() const {
  std::lock_guard<std::mutex> lock(mutex_);
  PoseEstimate e;
  if (!have_reading_) return e;
  e.valid = true;
  e.stamp = last_.stamp;
  e.pose = map_from_odom_ * last_.pose;
  // Odometry covariance grown since the anchor, rotated into the map frame, plus the anchor's.
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  r.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(map_from_odom_.theta).toRotationMatrix();
  Eigen::Matrix3d grown = last_.covariance - odom_covariance_at_anchor_;
  for (int i = 0; i < 3; ++i) grown(i, i) = std::max(0.0, grown(i, i));
  e.covariance = r * grown * r.transpose() + anchor_covariance_;
  return e;
}

}  // namespace navd::localization
