#pragma once
// Localisers against navsim's robot and laser in-process (the simulator library, no network):
// single simulated scans, and drives that feed a localiser odometry at 50 Hz and scans at 10 Hz
// as navd would and measure its error against the ground truth. Header-only: the unit tests and
// the localisation benchmarks share it.
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "services/common/diff_drive.h"
#include "services/common/ray_caster.h"
#include "services/common/world.h"
#include "services/localization/localizer.h"
#include "simulator/laser_scanner.h"
#include "simulator/scenario.h"
#include "simulator/simulation.h"

namespace navd::localization {

// One scan of `world`'s laser (with its noise) taken at `pose`, with the scan's header filled in.
inline ScanReading SimulatedScan(const World& world, const Pose2& pose, std::mt19937_64& rng) {
  const sim::LaserScanner laser(world.laser);
  ScanReading r;
  r.ranges = laser.Scan(pose, RayCaster(world.map), {}, -1, rng);
  r.angle_min = laser.angle_min();
  r.angle_increment = laser.increment();
  r.range_min = world.laser.range_min;
  r.range_max = world.laser.range_max;
  return r;
}

inline ScanReading ToScan(const sim::Simulation& s, const std::vector<float>& ranges) {
  ScanReading r;
  r.ranges = ranges;
  r.angle_min = s.robot().laser()->angle_min();
  r.angle_increment = s.robot().laser()->increment();
  r.range_min = s.world().laser.range_min;
  r.range_max = s.world().laser.range_max;
  r.stamp = s.now();
  return r;
}

struct Errors {
  double position = 0, heading = 0;  // worst over the settle window
  double mean_position = 0, mean_heading = 0;
};

// A systematic odometry error, as from a mis-measured wheel radius or wheel base: every increment's
// translation is scaled by 1 + scale and its rotation by 1 + turn.
struct OdometryBias {
  double scale = 0.0;
  double turn = 0.0;
};

// Runs `seconds` of simulation under `command`; returns the errors over the last `settle` seconds.
inline Errors Drive(sim::Simulation& s, Localizer& localizer, double seconds,
                    const std::function<Twist2(double)>& command, double settle, OdometryBias bias = {}) {
  Errors e;
  int samples = 0;
  Pose2 last_odom = s.robot().base().odom_pose(), biased = last_odom;
  const double end = s.now() + seconds;
  while (s.now() < end) {
    const Twist2 c = command(s.now());
    s.Command(0, {c.v, 0.0, c.omega});
    const auto out = s.Step();
    if (out.robots[0].odom) {
      const Pose2 odom = s.robot().base().odom_pose();
      const Pose2 d = last_odom.inverse() * odom;
      biased = biased * Pose2{d.x * (1 + bias.scale), d.y * (1 + bias.scale), d.theta * (1 + bias.turn)};
      last_odom = odom;
      localizer.AddOdometry({biased, s.robot().base().odom_covariance(), s.now()});
    }
    if (out.robots[0].scan) localizer.AddScan(ToScan(s, *out.robots[0].scan));
    if (s.now() > end - settle) {
      const Pose2 p = localizer.Estimate().pose, t = s.robot().base().true_pose();
      const double dp = std::hypot(p.x - t.x, p.y - t.y), dh = std::abs(NormalizeAngle(p.theta - t.theta));
      e.position = std::max(e.position, dp);
      e.heading = std::max(e.heading, dh);
      e.mean_position += dp;
      e.mean_heading += dh;
      ++samples;
    }
  }
  if (samples > 0) {
    e.mean_position /= samples;
    e.mean_heading /= samples;
  }
  return e;
}

// Up the default world's corridor for 20 s at 0.3 m/s, a half turn on the spot, and back.
inline Twist2 UpTheCorridorAndBack(double t) {
  if (t < 20) return Twist2{0.3, 0.0};
  if (t < 30) return Twist2{0.0, M_PI / 10};
  return Twist2{0.3, 0.0};
}

// Seed 000's validation case for pose correction (sections 4.3 and 5.3): the robot at
// (2.45, 4.23, pi) in the warehouse, a moving obstacle walking back and forth across the laser's
// view 1.25 m ahead, the estimate started at kValidationEstimate with 0.2 m / 0.2 rad of spread.
inline sim::Scenario SeedZeroValidationScenario() {
  World world = DefaultWorld();
  world.start = {2.45, 4.23, M_PI};
  sim::Scenario scenario = sim::ScenarioFromWorld(world);
  sim::MovingObstacleDescription walker;
  walker.name = "walker";
  walker.speed = 0.4;
  walker.loop = {{1.2, 3.0}, {1.2, 5.6}};
  scenario.moving_obstacles.push_back(walker);
  return scenario;
}
inline const Pose2 kValidationEstimate{2.25, 4.20, 3.0};

// Runs the case with `localizer` (anchored at the simulation's first odometry): the robot turns on
// the spot and back for 12 s (slowly enough, 0.3 rad/s, for seed 000's calibration to keep
// checking), then stands; returns the worst error over the last half second.
inline Errors RunSeedZeroValidation(sim::Simulation& s, Localizer& localizer) {
  localizer.AddOdometry({s.robot().base().odom_pose(), Eigen::Matrix3d::Zero(), 0.0});
  localizer.SetPose(kValidationEstimate, Eigen::Vector3d(0.04, 0.04, 0.04).asDiagonal());
  return Drive(
      s, localizer, 13.0,
      [](double t) {
        return Twist2{0.0, t < 6 ? 0.3 : t < 12 ? -0.3 : 0.0};
      },
      0.5);
}

}  // namespace navd::localization
