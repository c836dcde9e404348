// navsim's physics and sensors without DDS: ray casting, collisions, watchdog, encoders.
#include <gtest/gtest.h>

#include <cmath>

#include "services/common/world.h"
#include "simulator/laser_scanner.h"
#include "simulator/simulation.h"

namespace navd::sim {
namespace {

World BoxWorld() {
  // 4 x 4 m room with 0.1 m walls, robot in the middle facing +x.
  return ParseWorld(
      "map: {resolution: 0.05, size: [4, 4], boxes: [[0, 0, 4, 0.1], [0, 3.9, 4, 4], [0, 0, 0.1, 4], [3.9, 0, 4, 4]]}\n"
      "robot: {start: [2, 2, 0], actuator_noise: 0, encoder_noise: 0}\n"
      "laser: {noise: 0}\n",
      "box", ".");
}

TEST(LaserScanner, MeasuresDistancesToWalls) {
  const World w = BoxWorld();
  // Wall face at x = 3.9 (cells from 3.9 on): 1.9 m ahead.
  EXPECT_NEAR(LaserScanner::CastRay(w.map, {2, 2}, 0.0, 4.0), 1.9, 1e-9);
  EXPECT_NEAR(LaserScanner::CastRay(w.map, {2, 2}, M_PI, 4.0), 1.9, 1e-9);
  EXPECT_NEAR(LaserScanner::CastRay(w.map, {2, 2}, M_PI / 4, 4.0), 1.9 * std::sqrt(2.0), 0.08);
  EXPECT_NEAR(LaserScanner::CastRay(w.map, {2, 2}, 0.0, 1.0), 1.0, 1e-9);  // max range
}

TEST(LaserScanner, ScanHasUrg04lxGeometry) {
  const World w = DefaultWorld();
  LaserScanner laser(w.laser);
  std::mt19937_64 rng(1);
  const auto ranges = laser.Scan(w.start, w.map, rng);
  EXPECT_EQ(ranges.size(), 683u);
  EXPECT_NEAR(laser.angle_max() - laser.angle_min(), 240 * M_PI / 180, 1e-9);
  // In the corridor, walls are close on both sides: most beams return; those that do not read
  // range_max + 1.
  int returns = 0;
  for (float r : ranges) {
    if (r < 4.0f) ++returns;
    else EXPECT_EQ(r, 5.0f);
  }
  EXPECT_GT(returns, 400);
  // Beam at +90 deg (index 512 of 683 spanning -120..120) sees the corridor's left wall at x = 0.1.
  EXPECT_NEAR(ranges[(683 - 1) * 210 / 240], 0.7, 0.05);
}

TEST(Simulation, SensorsRunAtTheirOwnRates) {
  Simulation sim(BoxWorld(), {});
  int scans = 0, odoms = 0;
  for (int i = 0; i < 100; ++i) {  // one simulated second
    const StepOutputs out = sim.Step();
    scans += out.scan.has_value();
    odoms += out.odom;
  }
  EXPECT_NEAR(sim.now(), 1.0, 1e-9);
  EXPECT_EQ(scans, 10);
  EXPECT_EQ(odoms, 50);
}

TEST(Simulation, WatchdogStopsTheRobotWithoutCommands) {
  Simulation sim(BoxWorld(), {});
  sim.Command({0.2, 0.0});
  for (int i = 0; i < 50; ++i) sim.Step();  // 0.5 s: still moving
  EXPECT_GT(sim.robot().true_twist().v, 0.1);
  for (int i = 0; i < 50; ++i) sim.Step();  // command now older than 0.5 s
  EXPECT_TRUE(sim.watchdog_stopped());
  EXPECT_NEAR(sim.robot().true_twist().v, 0.0, 1e-9);
}

TEST(Simulation, RobotDoesNotPassThroughWallsAndCollisionsAreCounted) {
  Simulation sim(BoxWorld(), {});
  for (int i = 0; i < 1500; ++i) {
    sim.Command({0.5, 0.0});
    sim.Step();
  }
  EXPECT_LE(sim.robot().true_pose().x, 3.9 - 0.2 + 1e-9);
  EXPECT_GT(sim.robot().true_pose().x, 3.5);
  EXPECT_TRUE(sim.robot().in_collision());
  EXPECT_EQ(sim.robot().collisions(), 1u);
}

TEST(Simulation, OdometryTracksTruthWithNoiselessEncoders) {
  Simulation sim(BoxWorld(), {});
  for (int i = 0; i < 300; ++i) {
    sim.Command({0.2, 0.3});
    sim.Step();
  }
  const Pose2 truth = sim.world().start.inverse() * sim.robot().true_pose();  // odom starts at 0
  const Pose2 odom = sim.robot().odom_pose();
  // Only tick quantisation separates them (1024 ticks/rev of a 5 cm wheel: 0.3 mm/tick).
  EXPECT_NEAR(odom.x, truth.x, 0.005);
  EXPECT_NEAR(odom.y, truth.y, 0.005);
  EXPECT_NEAR(odom.theta, truth.theta, 0.01);
  EXPECT_GT(sim.robot().odom_covariance()(0, 0), 0.0);
}

TEST(Simulation, IgnoresNonFiniteCommands) {
  Simulation sim(BoxWorld(), {});
  sim.Command({NAN, 0.0});
  sim.Command({0.1, INFINITY});
  for (int i = 0; i < 20; ++i) sim.Step();
  EXPECT_TRUE(sim.robot().true_pose().finite());
  EXPECT_EQ(sim.robot().true_pose().x, 2.0);
  EXPECT_EQ(sim.robot().collisions(), 0u);
}

TEST(Simulation, SameSeedSameRun) {
  World w = DefaultWorld();
  SimulationOptions o;
  o.seed = 42;
  Simulation a(w, o), b(w, o);
  for (int i = 0; i < 200; ++i) {
    a.Command({0.2, 0.1});
    b.Command({0.2, 0.1});
    a.Step();
    b.Step();
  }
  EXPECT_EQ(a.robot().true_pose().x, b.robot().true_pose().x);
  EXPECT_EQ(a.robot().odom_pose().theta, b.robot().odom_pose().theta);
}

}  // namespace
}  // namespace navd::sim
