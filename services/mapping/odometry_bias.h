#pragma once
// The systematic part of a robot's odometry error, learnt from the front end's matches and taken
// out of each step before the step predicts the next scan's pose. A wheel radius a few percent off
// scales every step's translation; wheels of unequal radius turn the robot a little with every
// metre driven; a wheel base off scales its turns. Random error averages out over a run,
// systematic error does not: along a bare corridor, where only the odometry measures a step, a
// scale 3 % off stretches the corridor by 3 %, and a heading drift bends every stretch whose walls
// leave the heading to the odometry.
//
// The model of one step (x, y, θ) in the robot's frame where the step began:
//   translation  scale · (x, y)
//   turn         θ + turn_error · θ + drift · √(x² + y²)
// with the drift per metre the odometry reads (a robot whose odometry reads 3 % long and drifts
// 0.02 rad per true metre drifts 0.02 / 1.03 per metre read). The scale is the ratio of the
// matched travel to the odometry's over the steps whose walls fixed the match along the travel;
// the turn's two terms are fitted by least squares over the steps whose walls fixed the heading,
// each weighted by one over its travel (a heading's error grows with the distance driven), turns
// on the spot included. Along a corridor the match is the odometry's own prediction and says
// nothing of its error: the caller tells, per part, whether the walls fixed it. A prior holds the
// model at "no error" until enough steps speak, steps far off the model (a wrong match) are left
// out, and old steps fade with the distance driven, so an error that changes over a run (a load,
// a floor) is followed.
//
// Off in OdometryBiasOptions' defaults: the replay's noise model has no systematic part unless
// it is given one (odometry_noise.h), and a bias learnt from its random error alone is noise
// added to every prediction. A robot's own odometry (navd's mapping runs, navd-replay --odometry
// log) takes RobotOdometryBias(). Metres, radians.
#include <Eigen/Core>

#include "services/common/pose2.h"

namespace navd::mapping {

struct OdometryBiasOptions {
  bool enabled = false;
  double min_step = 0.1;  // m: shorter steps say too little of the scale or the drift, and
  double min_turn = 0.1;  // rad: a shorter step turning less says nothing of the turn error
  // The prior, "no error": worth as much as this much driving (m) whose walls fixed the step, for
  // the scale and the drift; for the turn error, as much as turns whose squared angle over their
  // travel (rad² per metre, at least min_step) add up to prior_turn.
  double prior_travel = 3.0;
  double prior_turn = 5.0;
  double memory = 300.0;  // m driven, over which a step's weight falls to 1/e
  // The model stays within these (beyond them the odometry is broken, not biased).
  double max_scale_error = 0.15;
  double max_drift = 0.1;  // rad/m
  double max_turn_error = 0.15;
  // A step that differs from the model's correction by more than this was matched wrong.
  double outlier_xy = 0.1;      // m
  double outlier_theta = 0.05;  // rad
};

// The options for a robot's own odometry: learning on.
OdometryBiasOptions RobotOdometryBias();

class OdometryBias {
 public:
  // Throws Error(kInvalidArgument) for options it cannot learn with (a prior, memory or least
  // step that is no positive amount, a bound or outlier gate below zero).
  explicit OdometryBias(const OdometryBiasOptions& options = {});

  // The odometry's `step` with the systematic error learnt so far taken out.
  Pose2 Correct(const Pose2& step) const;
  // The odometry's raw `step` and the step as matched, for every step driven (an unmatched one
  // with neither part fixed: it only fades the steps before); `translation_fixed`: the walls fixed
  // the matched translation along the step, `heading_fixed`: they fixed its heading.
  void Observe(const Pose2& step, const Pose2& matched, bool translation_fixed, bool heading_fixed);

  double scale() const { return scale_; }
  double drift() const { return drift_; }  // rad/m
  double turn_error() const { return turn_error_; }

 private:
  OdometryBiasOptions o_;
  // Translation: the matched travel along the odometry's, and the odometry's travel (m).
  double matched_travel_ = 0.0, travel_ = 0.0;
  // Heading: the normal equations of the turn's residual in (turn_error, drift).
  Eigen::Matrix2d turn_normal_ = Eigen::Matrix2d::Zero();
  Eigen::Vector2d turn_rhs_ = Eigen::Vector2d::Zero();
  double scale_ = 1.0, drift_ = 0.0, turn_error_ = 0.0;
};

}  // namespace navd::mapping
