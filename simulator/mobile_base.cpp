#include "simulator/mobile_base.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "services/common/diff_drive.h"

namespace navd::sim {

MobileBase::MobileBase(const RobotDescription& description, const Pose2& start, uint64_t seed)
    : d_(description), kinematics_(description), rng_(seed), pose_(start), proposed_(start) {
  wheels_n_ = kinematics_.wheels();
  ticks_.assign(wheels_n_, 0.0);
  counted_.assign(wheels_n_, 0);
}

Eigen::Vector3d MobileBase::WheelsOf(const BodyTwist& t) const {
  return kinematics_.WheelsOf(Eigen::Vector3d(t.vx, t.vy, t.omega));
}

BodyTwist MobileBase::TwistOf(const Eigen::Vector3d& wheels) const {
  const Eigen::Vector3d t = kinematics_.TwistOf(wheels);
  return {t.x(), t.y(), t.z()};
}

void MobileBase::ClampToLimits(Eigen::Vector3d& wheels) const {
  // Scale all wheels together so the motion keeps its direction and curvature.
  const double m = wheels.cwiseAbs().maxCoeff();
  if (m > d_.max_wheel_speed) wheels *= d_.max_wheel_speed / m;
}

void MobileBase::CommandVelocity(const BodyTwist& twist) {
  accel_mode_ = false;
  BodyTwist t = twist;
  if (d_.drive != DriveType::kOmni) t.vy = 0.0;
  if (d_.drive == DriveType::kUnicycle) {
    t.vx = std::clamp(t.vx, -d_.max_speed, d_.max_speed);
    t.omega = std::clamp(t.omega, -d_.max_angular_speed, d_.max_angular_speed);
  }
  velocity_target_ = t;
  target_ = WheelsOf(t);
  ClampToLimits(target_);
}

void MobileBase::CommandAcceleration(double linear, double angular) {
  accel_mode_ = true;
  u1_ = std::clamp(linear, -d_.max_accel, d_.max_accel);
  u2_ = std::clamp(angular, -d_.max_angular_accel, d_.max_angular_accel);
}

Pose2 MobileBase::ProposeMotion(double dt) {
  std::normal_distribution<double> unit(0.0, 1.0);
  if (d_.drive == DriveType::kUnicycle) {
    // Eq. 10: v' = u1, theta'' = u2. A velocity command becomes the accelerations that reach it
    // fastest within the limits.
    double u1 = u1_, u2 = u2_;
    if (!accel_mode_) {
      u1 = std::clamp((velocity_target_.vx - v_) / dt, -d_.max_accel, d_.max_accel);
      u2 = std::clamp((velocity_target_.omega - omega_) / dt, -d_.max_angular_accel, d_.max_angular_accel);
    }
    v_ = std::clamp(v_ + u1 * dt, -d_.max_speed, d_.max_speed);
    omega_ = std::clamp(omega_ + u2 * dt, -d_.max_angular_speed, d_.max_angular_speed);
    wheels_ = WheelsOf({v_, 0.0, omega_});
  } else {
    if (accel_mode_) {
      // Accelerations move the velocity target; the wheel dynamics below still apply.
      velocity_target_.vx += u1_ * dt;
      velocity_target_.omega += u2_ * dt;
      target_ = WheelsOf(velocity_target_);
      ClampToLimits(target_);
    }
    const double step = d_.max_wheel_accel * dt;
    for (int i = 0; i < wheels_n_; ++i) wheels_[i] += std::clamp(target_[i] - wheels_[i], -step, step);
  }
  // Each wheel achieves its speed with multiplicative noise (motor and floor variation).
  Eigen::Vector3d achieved = wheels_;
  for (int i = 0; i < wheels_n_; ++i) achieved[i] *= 1.0 + d_.actuator_noise * unit(rng_);
  travel_ = achieved * dt;
  twist_ = TwistOf(achieved);
  proposed_ = IntegrateTwist(pose_, twist_.vx * dt, twist_.vy * dt, twist_.omega * dt);
  return proposed_;
}

void MobileBase::CommitMotion(bool blocked, double dt) {
  std::normal_distribution<double> unit(0.0, 1.0);
  if (blocked) {
    // The robot stays where it is; its wheels stall.
    wheels_.setZero();
    travel_.setZero();
    v_ = omega_ = 0.0;
    twist_ = {};
  } else {
    distance_ += Distance(pose_.translation(), proposed_.translation());
    pose_ = proposed_;
  }
  // Encoders count whole ticks of the wheel's rotation, which slips a little against the floor.
  const double metres_per_tick = 2.0 * M_PI * d_.wheel_radius / d_.encoder_ticks_per_rev;
  Eigen::Vector3d measured = Eigen::Vector3d::Zero();
  Eigen::Vector3d variance = Eigen::Vector3d::Zero();
  for (int i = 0; i < wheels_n_; ++i) {
    ticks_[i] += travel_[i] * (1.0 + d_.encoder_noise * unit(rng_)) / metres_per_tick;
    const long long whole = static_cast<long long>(std::floor(ticks_[i]));
    measured[i] = (whole - counted_[i]) * metres_per_tick;
    counted_[i] = whole;
    variance[i] = std::pow(d_.encoder_noise * measured[i], 2) +
                  (measured[i] != 0.0 ? metres_per_tick * metres_per_tick / 12.0 : 0.0);
  }
  const BodyTwist step = TwistOf(measured);
  odom_twist_ = {step.vx / dt, step.vy / dt, step.omega / dt};
  odom_pose_ = IntegrateTwist(odom_pose_, step.vx, step.vy, step.omega);
  // Odometry uncertainty grows with wheel travel: body-frame covariance of this step, rotated
  // into the odometry frame.
  const Eigen::Matrix3d body = kinematics_.TwistCovariance(variance);
  Eigen::Matrix3d rot = Eigen::Matrix3d::Identity();
  const double c = std::cos(odom_pose_.theta), s = std::sin(odom_pose_.theta);
  rot.topLeftCorner<2, 2>() << c, -s, s, c;
  odom_cov_ += rot * body * rot.transpose();
}

std::vector<double> MobileBase::wheel_angles() const {
  std::vector<double> out;
  for (long long t : counted_) out.push_back(2.0 * M_PI * t / d_.encoder_ticks_per_rev);
  return out;
}

}  // namespace navd::sim
