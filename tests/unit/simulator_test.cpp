// navsim without DDS: ray casting, kinematics of each drive, each sensor against hand-computed
// geometry, people's motion statistics, scripted obstacles, several robots, scenarios and their
// errors, determinism, and the CARMEN recorder's round trip.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <cmath>
#include <filesystem>
#include <cstring>
#include <fstream>

#include "services/common/carmen_log.h"
#include "services/common/error.h"
#include "services/common/grid_traversal.h"
#include "services/common/ziggurat_normal.h"
#include "services/common/polygon.h"
#include "services/common/world.h"
#include "simulator/carmen_recorder.h"
#include "simulator/laser_scanner.h"
#include "simulator/lockstep_gate.h"
#include "simulator/simulation.h"
#include "tests/support/process.h"

namespace navd::sim {
namespace {

// 4 x 4 m room with 0.1 m walls; the robot in the middle facing +x; no noise anywhere.
const char* kBoxWorld =
    "map: {resolution: 0.05, size: [4, 4], boxes: [[0, 0, 4, 0.1], [0, 3.9, 4, 4], [0, 0, 0.1, 4], [3.9, 0, 4, 4]]}\n"
    "robot: {start: [2, 2, 0], actuator_noise: 0, encoder_noise: 0}\n"
    "laser: {noise: 0}\n";

World BoxWorld() { return ParseWorld(kBoxWorld, "box", "."); }

// One fresh folder for this process's files, removed at exit: a folder named by the process id
// can hold an earlier run's files once the id comes round again.
std::string TempDir() {
  static const std::string dir = testing::MakeTempDir();
  return dir;
}

std::string WriteFile(const std::string& name, const std::string& text) {
  std::string path = TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

Scenario ScenarioText(const std::string& robots_and_more) {
  const std::string world = WriteFile("box.yaml", kBoxWorld);
  return ParseScenario("world: " + world + "\n" + robots_and_more, "test.yaml", ".");
}

// The reference: a plain cell walk with the exact traversal.
double WalkRay(const OccupancyGrid& map, const Point2& o, const Point2& dir, double max_range) {
  double hit = max_range;
  TraverseSegment(map, o, o + max_range * dir, [&](const CellIndex& c, double t) {
    if (map.Contains(c) && !map.IsOccupied(c)) return true;
    hit = std::min(hit, t);
    return false;
  });
  return hit;
}
double WalkRay(const OccupancyGrid& map, const Point2& o, double angle, double max_range) {
  return WalkRay(map, o, Point2(std::cos(angle), std::sin(angle)), max_range);
}

TEST(RayCaster, MeasuresDistancesToWalls) {
  const RayCaster walls(BoxWorld().map);
  // Wall face at x = 3.9: 1.9 m ahead; likewise behind.
  EXPECT_NEAR(walls.Cast({2, 2}, 0.0, 4.0), 1.9, 1e-9);
  EXPECT_NEAR(walls.Cast({2, 2}, M_PI, 4.0), 1.9, 1e-9);
  EXPECT_NEAR(walls.Cast({2, 2}, M_PI / 4, 4.0), 1.9 * std::sqrt(2.0), 1e-9);  // into the corner
  EXPECT_NEAR(walls.Cast({2, 2}, 0.0, 1.0), 1.0, 1e-9);                        // max range
}

// To a sensor the map's edge is open: rays that leave the grid read max_range, while walls on the
// grid's edge rows and columns are hit as any other, also from inside the edge row (a door jamb)
// and at grazing angles.
TEST(RayCaster, TheMapsEdgeIsOpenToSensors) {
  OccupancyGrid map(100, 40, 0.1, {0, 0});
  for (int x = 0; x < 40; ++x) map.set({x, 0}, OccupancyGrid::kOccupied);    // wall along y in [0, 0.1], x < 4
  for (int y = 10; y < 40; ++y) map.set({99, y}, OccupancyGrid::kOccupied);  // wall along x in [9.9, 10], y >= 1
  const RayCaster caster(map);
  EXPECT_NEAR(caster.Cast({0.5, 2.0}, M_PI, 30.0), 0.5, 1e-9);  // the edge as a wall
  EXPECT_EQ(caster.CastOpenEdge({0.5, 2.0}, M_PI, 30.0), 30.0);
  EXPECT_EQ(caster.CastOpenEdge({5.0, 2.0}, M_PI / 2, 30.0), 30.0);
  EXPECT_NEAR(caster.CastOpenEdge({2.0, 2.0}, -M_PI / 2, 30.0), 1.9, 1e-9);
  EXPECT_NEAR(caster.CastOpenEdge({5.0, 0.05}, M_PI, 30.0), 1.0, 1e-9);      // the wall's end, from inside the edge row
  EXPECT_EQ(caster.CastOpenEdge({5.0, 0.05}, 0.0, 30.0), 30.0);              // out through the gap at x = 10
  EXPECT_NEAR(caster.CastOpenEdge({9.95, 0.5}, M_PI / 2, 30.0), 0.5, 1e-9);  // up the edge column into its wall
  // Grazing the edge walls at 5 degrees: the wall along y = 0.1 (up to x = 4) or the one along
  // x = 9.9 (from y = 1), or out of the grid past them.
  const double down = M_PI + 5 * M_PI / 180, up = M_PI / 2 - 5 * M_PI / 180;
  EXPECT_NEAR(caster.CastOpenEdge({6.0, 0.3}, down, 30.0), 0.2 / std::sin(5 * M_PI / 180), 1e-9);
  EXPECT_NEAR(caster.CastOpenEdge({6.0, 0.6}, down, 30.0), 0.5 / std::sin(5 * M_PI / 180), 1e-9);
  EXPECT_EQ(caster.CastOpenEdge({6.0, 0.9}, down, 30.0), 30.0);  // out at x = 0, y = 0.38
  EXPECT_NEAR(caster.CastOpenEdge({9.8, 1.5}, up, 30.0), 0.1 / std::sin(5 * M_PI / 180), 1e-9);
  EXPECT_EQ(caster.CastOpenEdge({9.0, 1.5}, up, 30.0), 30.0);  // out at y = 4, x = 9.22
  // The corner cell's top face, 2 cm from the grid's edge, the ray heading out through that edge.
  EXPECT_NEAR(caster.CastOpenEdge({1.0, 1.0}, std::atan2(-0.9, -0.98), 30.0), std::hypot(0.98, 0.9), 1e-9);
}

TEST(RayCaster, BlockLeapsGiveExactlyTheCellWalksHits) {
  // A cluttered 1000 x 1000 grid: leaping over empty blocks must never skip an obstacle.
  OccupancyGrid map(1000, 1000, 0.05, {0, 0});
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 50), a(-M_PI, M_PI), size(0.05, 1.0);
  for (int i = 0; i < 400; ++i) {
    const Point2 c(u(rng), u(rng));
    const double s = size(rng);
    map.FillBox(c, c + Point2(s, s * 0.3));
  }
  const RayCaster caster(map);
  int compared = 0;
  for (int i = 0; i < 20000; ++i) {
    const Point2 o(u(rng), u(rng));
    if (map.IsOccupied(map.CellOf(o))) continue;
    const double angle = a(rng);
    ASSERT_NEAR(caster.Cast(o, angle, 4.0), WalkRay(map, o, angle, 4.0), 1e-9) << "ray " << i;
    ++compared;
  }
  EXPECT_GT(compared, 15000);
  // Rays along the axes and diagonals from cell centres and corners cross cell corners exactly,
  // where the side cells count: the leaps must take the same corners as the walk.
  // Exact directions: cos(pi / 2) is 6e-17, not 0, and which side of a boundary such a ray runs
  // is then decided by rounding.
  const double h = std::sqrt(0.5);
  const Point2 dirs[8] = {{1, 0}, {h, h}, {0, 1}, {-h, h}, {-1, 0}, {-h, -h}, {0, -1}, {h, -h}};
  std::uniform_int_distribution<int> cell(0, 999), octant(0, 7), corner(0, 1);
  int aligned = 0;
  for (int i = 0; i < 20000; ++i) {
    const double off = corner(rng) ? 0.0 : 0.025;
    const Point2 o(cell(rng) * 0.05 + off, cell(rng) * 0.05 + off);
    if (map.IsOccupied(map.CellOf(o))) continue;
    const Point2& dir = dirs[octant(rng)];
    ASSERT_NEAR(caster.Cast(o, dir, 4.0), WalkRay(map, o, dir, 4.0), 1e-9)
        << "aligned ray " << i << " from " << o.transpose() << " along " << dir.transpose();
    ++aligned;
  }
  EXPECT_GT(aligned, 15000);
}

TEST(ZigguratNormal, MatchesTheNormalDistributionIncludingItsTails) {
  std::mt19937_64 rng(11);
  constexpr int kSamples = 1000000;
  std::vector<double> x(kSamples);
  double sum = 0, sum_sq = 0;
  int tail = 0;
  for (double& v : x) {
    v = ZigguratNormal::Standard(rng);
    sum += v;
    sum_sq += v * v;
    tail += std::abs(v) > 3.442619855899;  // drawn by the tail sampler, not the layers
  }
  EXPECT_NEAR(sum / kSamples, 0.0, 5 * 1.0 / std::sqrt(kSamples));
  EXPECT_NEAR(sum_sq / kSamples, 1.0, 5 * std::sqrt(2.0 / kSamples));
  // P(|X| > 3.4426) = 5.76e-4: 576 expected, sd 24.
  EXPECT_NEAR(tail, 576, 120);
  // Kolmogorov-Smirnov against the normal CDF; 1.95 / sqrt(n) is the 0.1% critical value.
  std::sort(x.begin(), x.end());
  double d = 0;
  for (int i = 0; i < kSamples; i += 7) {
    const double cdf = 0.5 * std::erfc(-x[i] / std::sqrt(2.0));
    d = std::max({d, std::abs(cdf - static_cast<double>(i) / kSamples), std::abs(cdf - (i + 1.0) / kSamples)});
  }
  EXPECT_LT(d, 1.95 / std::sqrt(kSamples));
  // Scaled and shifted like std::normal_distribution, and deterministic for a seed.
  std::mt19937_64 a(5), b(5);
  const ZigguratNormal noise(2.0, 0.1);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(noise(a), 2.0 + 0.1 * ZigguratNormal::Standard(b));
}

TEST(Doors, OpenAndCloseAtRunTimeButNeverOnABody) {
  Scenario office = LoadScenarioFile(std::string(NAVD_SOURCE_DIR) + "/worlds/scenarios/office.yaml");
  ASSERT_EQ(office.doors.size(), 8u);
  office.robots[0].start = Pose2(17.5, 4.95, -M_PI / 2);  // in doorway s4
  Simulation sim(office, {});
  // Open: the ray from the corridor down through the doorway runs into the room beyond y = 4.9.
  const double open = sim.truth().Cast({2.5, 6.0}, -M_PI / 2, 4.0);
  EXPECT_GT(open, 1.2);
  sim.SetDoor("s1", true);
  EXPECT_NEAR(sim.truth().Cast({2.5, 6.0}, -M_PI / 2, 4.0), 1.0, 1e-9);  // the door's face at y = 5.0
  EXPECT_TRUE(sim.scenario().doors[0].closed);
  EXPECT_FALSE(sim.world().map.IsOccupied(sim.world().map.CellOf({2.5, 4.95})));  // not in the robots' map
  sim.SetDoor("s1", false);
  EXPECT_DOUBLE_EQ(sim.truth().Cast({2.5, 6.0}, -M_PI / 2, 4.0), open);

  const auto refused = [&](const std::string& name, ErrorCode code, const std::string& text) {
    try {
      sim.SetDoor(name, true);
      ADD_FAILURE() << "closing " << name << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), code);
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  refused("s9", ErrorCode::kNotFound, "no door 's9' (doors: s1, s2, s3, s4, n1, n2, n3, n4)");
  // The robot stands in doorway s4: the door does not shut on it.
  refused("s4", ErrorCode::kFailedPrecondition, "door 's4' cannot close on");
  EXPECT_FALSE(sim.scenario().doors[3].closed);
}

TEST(RayCaster, RayDiscDistance) {
  const Disc d{{3, 0}, 0.5, 1};
  EXPECT_NEAR(RayDiscDistance({0, 0}, {1, 0}, d), 2.5, 1e-12);
  EXPECT_TRUE(std::isinf(RayDiscDistance({0, 0}, {-1, 0}, d)));  // behind
  EXPECT_TRUE(std::isinf(RayDiscDistance({0, 1}, {1, 0}, d)));   // passes above
  // Tangent-ish: at height 0.3 the chord starts at 3 - sqrt(0.25 - 0.09) = 2.6.
  EXPECT_NEAR(RayDiscDistance({0, 0.3}, {1, 0}, d), 2.6, 1e-12);
}

TEST(LaserScanner, ScanHasUrg04lxGeometry) {
  const World w = DefaultWorld();
  LaserScanner laser(w.laser);
  std::mt19937_64 rng(1);
  const auto ranges = laser.Scan(w.start, RayCaster(w.map), {}, -1, rng);
  EXPECT_EQ(ranges.size(), 683u);
  EXPECT_NEAR(laser.angle_max() - laser.angle_min(), 240 * M_PI / 180, 1e-9);
  int returns = 0;
  for (float r : ranges) {
    if (r < 4.0f)
      ++returns;
    else
      EXPECT_EQ(r, 5.0f);  // no return reads range_max + 1
  }
  EXPECT_GT(returns, 400);
  // Beam at +90 degrees sees the corridor's left wall at x = 0.1 from x = 0.8.
  EXPECT_NEAR(ranges[(683 - 1) * 210 / 240], 0.7, 0.05);
}

TEST(LaserScanner, SeesDiscsButNotItsOwnRobot) {
  const World w = BoxWorld();
  LaserDescription d = w.laser;
  d.beams = 241;  // one beam per degree over 240 degrees; beam 120 points straight ahead
  LaserScanner laser(d);
  std::mt19937_64 rng(1);
  const std::vector<Disc> discs = {{{2, 2}, 0.2, 0}, {{3, 2}, 0.25, 7}};
  const auto ranges = laser.Scan({2, 2, 0}, RayCaster(w.map), discs, 0, rng);
  EXPECT_NEAR(ranges[120], 0.75, 1e-6);                    // person's near edge at x = 2.75
  EXPECT_NEAR(ranges[0], 1.9 / std::sin(M_PI / 3), 1e-3);  // -120 degrees: the wall y = 0.1, unobstructed
}

// The street of book chapter 7 is open at its ends: a laser there sees the wall along its side and
// nothing out of the open end (the ray caster's edge of the map is no wall to a sensor), while a
// wall on the map's edge row is seen as any other.
TEST(LaserScanner, SeesNothingBeyondTheMapsOpenEdge) {
  OccupancyGrid street(100, 40, 0.1, {0, 0});                                  // 10 m x 4 m
  for (int x = 0; x < 100; ++x) street.set({x, 0}, OccupancyGrid::kOccupied);  // a wall along y in [0, 0.1]
  LaserDescription d;
  d.fov = 2 * M_PI;
  d.beams = 361;  // beam i at -180 + i degrees
  d.range_max = 30.0;
  d.noise = 0.0;
  LaserScanner laser(d);
  std::mt19937_64 rng(1);
  const auto ranges = laser.Scan({0.5, 2.0, 0.0}, RayCaster(street), {}, -1, rng);
  const float none = 31.0f;            // no return reads range_max + 1
  EXPECT_EQ(ranges[0], none);          // -180 degrees: out of the open end 0.5 m behind
  EXPECT_EQ(ranges[180], none);        // ahead: out of the far end, 9.5 m on
  EXPECT_EQ(ranges[270], none);        // +90 degrees: the map's edge at y = 4, no wall there
  EXPECT_NEAR(ranges[90], 1.9, 1e-6);  // -90 degrees: the wall on the edge row
  // A person standing in the open end is seen.
  const auto with_person = laser.Scan({0.5, 2.0, 0.0}, RayCaster(street), {{{0.2, 2.0}, 0.1, 3}}, -1, rng);
  EXPECT_NEAR(with_person[0], 0.2, 1e-6);
}

TEST(RangeSensors, SonarConeSeesWhatItsAxisMisses) {
  const World w = BoxWorld();
  const RayCaster walls(w.map);
  std::mt19937_64 rng(1);
  RangeArrayDescription d = PioneerSonarRing(0.2);
  d.noise = 0;
  d.angles = {0.0};
  d.cone = 0.0;
  d.rays_per_cone = 1;
  // On the rim at x = 2.2, facing the wall at 3.9: 1.7 m.
  EXPECT_NEAR(RangeSensorArray(d).Read({2, 2, 0}, walls, {}, -1, rng)[0], 1.7, 1e-6);
  // A post 1 m ahead and 0.15 m to the side: the axis misses it, a 15 degree cone does not.
  const std::vector<Disc> post = {{{3.2, 2.15}, 0.05, 5}};
  EXPECT_NEAR(RangeSensorArray(d).Read({2, 2, 0}, walls, post, -1, rng)[0], 1.7, 1e-6);
  d.cone = 15 * M_PI / 180;
  d.rays_per_cone = 5;
  EXPECT_LT(RangeSensorArray(d).Read({2, 2, 0}, walls, post, -1, rng)[0], 1.0);
  // The Pioneer ring has 16 sonars, 8 facing forward.
  EXPECT_EQ(PioneerSonarRing(0.2).angles.size(), 16u);
}

// A glass pane: the bumpers and the sonar find it, the laser sees through it; a plain box is seen by both.
TEST(Scenarios, GlassIsSeenBySonarButNotByTheLaser) {
  const Scenario s = ScenarioText(
      "hidden_obstacles: {glass: [[3.0, 1.5, 3.1, 2.5]], boxes: [[1.0, 0.9, 1.2, 1.1]]}\n"
      "robots: [{start: [2, 2, 0], sensors: [{type: laser}, {type: sonar}]}]\n");
  EXPECT_EQ(s.hidden_obstacles, 2);
  EXPECT_FALSE(s.see_through.empty());
  SimulationOptions options;
  Simulation sim(s, options);
  std::optional<std::vector<float>> scan, sonar;
  while (!scan || !sonar) {
    auto out = sim.Step();
    if (out.robots[0].scan) scan = out.robots[0].scan;
    if (out.robots[0].sonar) sonar = out.robots[0].sonar;
  }
  const size_t ahead = static_cast<size_t>(s.robots[0].laser->beams - 1) / 2;
  EXPECT_GT((*scan)[ahead], 1.5f);     // through the pane to the wall at 3.9
  EXPECT_NEAR((*sonar)[3], 0.8, 0.1);  // sonar_3 (10 degrees left) echoes off the pane at x = 3.0
  EXPECT_TRUE(sim.truth().DiscHitsWall({3.05, 2.0}, 0.01));
  EXPECT_FALSE(sim.laser_truth().DiscHitsWall({3.05, 2.0}, 0.01));
  EXPECT_TRUE(sim.laser_truth().DiscHitsWall({1.1, 1.0}, 0.01));  // the box is no glass
}

TEST(RangeSensors, IrTripleOfSeed000) {
  const RayCaster walls(BoxWorld().map);
  std::mt19937_64 rng(1);
  RangeArrayDescription d = Gp2d12Triple(0.2);
  d.noise = 0;
  // Robot 0.5 m from the wall behind it (x = 0.1 face at 0.1): rear IR on the rim at x = 0.4 reads 0.3.
  const auto r = RangeSensorArray(d).Read({0.6, 2, 0}, walls, {}, -1, rng);
  ASSERT_EQ(r.size(), 3u);
  EXPECT_NEAR(r[2], 0.3, 1e-6);
  EXPECT_NEAR(r[0], 0.8, 1e-6);  // front sensors: nothing within 0.8 m
  EXPECT_NEAR(r[1], 0.8, 1e-6);
}

// Drives robot 0 of `sim` with `twist` for `seconds`.
void Drive(Simulation& sim, const BodyTwist& twist, double seconds) {
  const int steps = static_cast<int>(std::lround(seconds / sim.options().physics_step));
  for (int i = 0; i < steps; ++i) {
    sim.Command(0, twist);
    sim.Step();
  }
}

TEST(Kinematics, DifferentialDriveFollowsTheArcOfItsTwist) {
  Simulation sim(BoxWorld(), {});
  Drive(sim, {0.2, 0.0, 0.0}, 0.2);  // accelerate (0.2 m/s at 2 m/s^2 takes 0.1 s)
  const Pose2 a = sim.robot().base().true_pose();
  Drive(sim, {0.2, 0.5, 0.4}, 2.0);  // vy is ignored: a differential drive cannot slide
  const Pose2 rel = a.inverse() * sim.robot().base().true_pose();
  // After the 0.1 s wheel transient, an arc of radius v / omega = 0.5 m.
  const double r = 0.5;
  EXPECT_NEAR(rel.theta, 0.4 * 2.0 - 0.4 * 0.05, 0.02);
  EXPECT_NEAR(std::hypot(rel.x - 0.0, rel.y - r), r, 0.01);  // stays on the circle about (0, r)
  EXPECT_NEAR(sim.robot().base().true_twist().vy, 0.0, 1e-12);
}

TEST(Kinematics, OmniWheelSpeedsFollowEquation12AndItSlidesSideways) {
  World w = BoxWorld();
  w.robot.drive = DriveType::kOmni;
  w.robot.max_wheel_accel = 100.0;
  Simulation sim(w, {});
  Drive(sim, {0.0, 0.3, 0.0}, 2.0);
  const Pose2 p = sim.robot().base().true_pose();
  EXPECT_NEAR(p.x, 2.0, 1e-9);
  EXPECT_NEAR(p.y, 2.0 + 0.3 * 2.0, 0.01);
  EXPECT_NEAR(p.theta, 0.0, 1e-9);
  // Eq. 12 in the robot frame: v_i = -sin(a_i) vx + cos(a_i) vy + R omega.
  Drive(sim, {0.1, -0.1, 0.5}, 0.5);
  const auto v = sim.robot().base().wheel_speeds();
  ASSERT_EQ(v.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const double a = w.robot.omni_wheel_angles[i];
    EXPECT_NEAR(v[i], -std::sin(a) * 0.1 + std::cos(a) * -0.1 + w.robot.omni_wheel_distance * 0.5, 1e-9);
  }
  // Encoders on three wheels give odometry that tracks the truth.
  const Pose2 truth = w.start.inverse() * sim.robot().base().true_pose();
  EXPECT_NEAR(sim.robot().base().odom_pose().x, truth.x, 0.01);
  EXPECT_NEAR(sim.robot().base().odom_pose().y, truth.y, 0.01);
}

TEST(Kinematics, UnicycleIntegratesItsAccelerationInputs) {
  World w = BoxWorld();
  w.robot.drive = DriveType::kUnicycle;
  w.robot.max_accel = 1.0;
  w.robot.max_speed = 0.4;
  w.start = {0.5, 2.0, 0.0};
  Simulation sim(w, {});
  // Eq. 10: v' = u1. 0.5 m/s^2 for 0.5 s reaches 0.25 m/s having covered about 0.0625 m.
  for (int i = 0; i < 50; ++i) {
    sim.CommandAcceleration(0, 0.5, 0.0);
    sim.Step();
  }
  EXPECT_NEAR(sim.robot().base().true_twist().vx, 0.25, 1e-9);
  EXPECT_NEAR(sim.robot().base().true_pose().x - 0.5, 0.0625, 0.003);
  // u1 beyond the limit is clamped; speed saturates at max_speed.
  for (int i = 0; i < 100; ++i) {
    sim.CommandAcceleration(0, 5.0, 0.0);
    sim.Step();
  }
  EXPECT_NEAR(sim.robot().base().true_twist().vx, 0.4, 1e-9);
  // theta'' = u2: 2 rad/s^2 for 0.5 s gives 1 rad/s.
  for (int i = 0; i < 50; ++i) {
    sim.CommandAcceleration(0, 0.0, 2.0);
    sim.Step();
  }
  EXPECT_NEAR(sim.robot().base().true_twist().omega, 1.0, 1e-9);
}

TEST(Simulation, SensorsRunAtTheirOwnRates) {
  Scenario s = ScenarioFromWorld(BoxWorld());
  s.robots[0].sonar = PioneerSonarRing(0.2);
  s.robots[0].ir = Gp2d12Triple(0.2);
  Simulation sim(s, {});
  int scans = 0, odoms = 0, sonar = 0, ir = 0, encoders = 0, bumper = 0;
  for (int i = 0; i < 100; ++i) {  // one simulated second
    const StepOutputs out = sim.Step();
    scans += out.robots[0].scan.has_value();
    sonar += out.robots[0].sonar.has_value();
    ir += out.robots[0].ir.has_value();
    odoms += out.robots[0].odom;
    encoders += out.robots[0].encoders;
    bumper += out.robots[0].bumper;
  }
  EXPECT_NEAR(sim.now(), 1.0, 1e-9);
  EXPECT_EQ(scans, 10);
  EXPECT_EQ(sonar, 10);
  EXPECT_EQ(ir, 25);
  EXPECT_EQ(odoms, 50);
  EXPECT_EQ(encoders, 50);
  EXPECT_EQ(bumper, 10);
}

TEST(Simulation, WatchdogStopsTheRobotWithoutCommands) {
  Simulation sim(BoxWorld(), {});
  sim.Command(0, {0.2, 0.0, 0.0});
  for (int i = 0; i < 50; ++i) sim.Step();  // 0.5 s: still moving
  EXPECT_GT(sim.robot().base().true_twist().vx, 0.1);
  for (int i = 0; i < 50; ++i) sim.Step();  // command now older than 0.5 s
  EXPECT_TRUE(sim.robot().watchdog_stopped());
  for (int i = 0; i < 20; ++i) sim.Step();  // decelerating at the wheel limit
  EXPECT_NEAR(sim.robot().base().true_twist().vx, 0.0, 1e-9);
}

TEST(Simulation, WallsStopTheRobotPressItsBumperAndCountOnce) {
  Simulation sim(BoxWorld(), {});
  Drive(sim, {0.5, 0.0, 0.0}, 15.0);
  EXPECT_LE(sim.robot().base().true_pose().x, 3.9 - 0.2 + 1e-9);
  EXPECT_GT(sim.robot().base().true_pose().x, 3.5);
  EXPECT_TRUE(sim.robot().in_collision());
  EXPECT_EQ(sim.robot().collisions(), 1u);
  EXPECT_TRUE(sim.robot().bumper().front);
  EXPECT_FALSE(sim.robot().bumper().rear);
  // Backing into the wall behind presses the rear bumper: a second collision.
  Drive(sim, {-0.5, 0.0, 0.0}, 15.0);
  EXPECT_TRUE(sim.robot().bumper().rear);
  EXPECT_EQ(sim.robot().collisions(), 2u);
}

TEST(Simulation, OdometryTracksTruthWithNoiselessEncoders) {
  Simulation sim(BoxWorld(), {});
  Drive(sim, {0.2, 0.0, 0.3}, 3.0);
  const Pose2 truth = sim.world().start.inverse() * sim.robot().base().true_pose();  // odom starts at 0
  const Pose2 odom = sim.robot().base().odom_pose();
  // Only tick quantisation separates them (1024 ticks/rev of a 5 cm wheel: 0.3 mm/tick).
  EXPECT_NEAR(odom.x, truth.x, 0.005);
  EXPECT_NEAR(odom.y, truth.y, 0.005);
  EXPECT_NEAR(odom.theta, truth.theta, 0.01);
  EXPECT_GT(sim.robot().base().odom_covariance()(0, 0), 0.0);
  // 24-hole encoder wheels (seed 000) count 24 ticks per turn.
  World w = BoxWorld();
  w.robot.encoder_ticks_per_rev = 24;
  Simulation coarse(w, {});
  Drive(coarse, {0.2, 0.0, 0.0}, 1.0);
  const double turns = coarse.robot().base().distance_travelled() / (2 * M_PI * w.robot.wheel_radius);
  EXPECT_NEAR(coarse.robot().base().encoder_ticks()[0], 24 * turns, 1.0);
}

TEST(Simulation, IgnoresNonFiniteCommands) {
  Simulation sim(BoxWorld(), {});
  sim.Command(0, {NAN, 0.0, 0.0});
  sim.Command(0, {0.1, 0.0, INFINITY});
  sim.CommandAcceleration(0, NAN, 0.0);
  for (int i = 0; i < 20; ++i) sim.Step();
  EXPECT_TRUE(sim.robot().base().true_pose().finite());
  EXPECT_EQ(sim.robot().base().true_pose().x, 2.0);
}

TEST(Simulation, TwoRobotsSeeAndBumpIntoEachOther) {
  const Scenario s = ScenarioText(
      "robots:\n"
      "  - {name: alpha, start: [1.0, 2.0, 0.0], actuator_noise: 0, encoder_noise: 0}\n"
      "  - {name: beta, start: [3.0, 2.0, 3.14159265], actuator_noise: 0, encoder_noise: 0}\n");
  Simulation sim(s, {});
  const StepOutputs first = [&] {
    StepOutputs o;
    while (!o.robots.size() || !o.robots[0].scan) o = sim.Step();
    return o;
  }();
  // alpha's straight-ahead beam hits beta's near side at x = 2.8: 1.8 m.
  const auto& laser = *sim.robot(0).laser();
  const int ahead = static_cast<int>(std::lround(-laser.angle_min() / laser.increment()));
  EXPECT_NEAR((*first.robots[0].scan)[ahead], 1.8, 0.05);
  std::vector<CollisionEvent> events;
  for (int i = 0; i < 800; ++i) {
    sim.Command(0, {0.3, 0.0, 0.0});
    sim.Command(1, {0.3, 0.0, 0.0});
    const auto out = sim.Step();
    events.insert(events.end(), out.events.begin(), out.events.end());
  }
  EXPECT_NEAR(Distance(sim.robot(0).base().true_pose().translation(), sim.robot(1).base().true_pose().translation()),
              0.4, 0.02);
  ASSERT_EQ(events.size(), 2u);
  std::sort(events.begin(), events.end(), [](const auto& a, const auto& b) { return a.robot < b.robot; });
  EXPECT_EQ(events[0].robot, "alpha");
  EXPECT_EQ(events[0].other, "beta");
  EXPECT_EQ(events[1].robot, "beta");
  EXPECT_EQ(events[1].other, "alpha");
  // Who closed the gap: both drove at 0.3 m/s; the first to touch met the other still driving at
  // it, the second met one the contact had stalled.
  EXPECT_NEAR(events[0].robot_closing, 0.3, 0.01);
  EXPECT_NEAR(events[1].robot_closing, 0.3, 0.01);
  EXPECT_NEAR(std::max(events[0].other_closing, events[1].other_closing), 0.3, 0.01);
  EXPECT_NEAR(std::min(events[0].other_closing, events[1].other_closing), 0.0, 1e-9);
}

TEST(Simulation, AWallContactIsTheRobotClosingTheGap) {
  Simulation sim(BoxWorld(), {});
  std::vector<CollisionEvent> events;
  for (int i = 0; i < 1500 && events.empty(); ++i) {
    sim.Command(0, {0.5, 0.0, 0.0});
    const auto out = sim.Step();
    events.insert(events.end(), out.events.begin(), out.events.end());
  }
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].other, "wall");
  EXPECT_NEAR(events[0].robot_closing, 0.5, 0.05);  // the wheels' achieved speed varies by 2%
  EXPECT_EQ(events[0].other_closing, 0.0);
}

TEST(MovingObstacles, LoopAtTheirSpeedAndWaitForRobots) {
  const Scenario s = ScenarioText(
      "robots: [{start: [2.0, 3.0, 0.0]}]\n"
      "moving_obstacles:\n"
      "  - {name: cart, radius: 0.2, speed: 0.5, loop: [[1.0, 1.0], [3.0, 1.0]]}\n");
  Simulation sim(s, {});
  ASSERT_EQ(sim.moving_obstacles().size(), 1u);
  EXPECT_NEAR(sim.moving_obstacles()[0].loop_length(), 4.0, 1e-12);
  for (int i = 0; i < 200; ++i) sim.Step();  // 2 s at 0.5 m/s: 1 m along
  EXPECT_NEAR(sim.moving_obstacles()[0].position().x(), 2.0, 1e-6);
  for (int i = 0; i < 600; ++i) sim.Step();  // 8 s in total: a whole loop
  EXPECT_NEAR(sim.moving_obstacles()[0].position().x(), 1.0, 1e-6);
  // A robot standing on the loop holds it up; that is not the robot's collision.
  const Scenario blocked = ScenarioText(
      "robots: [{start: [2.0, 1.0, 0.0]}]\n"
      "moving_obstacles:\n"
      "  - {name: cart, radius: 0.2, speed: 0.5, loop: [[1.0, 1.0], [3.0, 1.0]]}\n");
  Simulation sim2(blocked, {});
  for (int i = 0; i < 400; ++i) sim2.Step();
  EXPECT_NEAR(sim2.moving_obstacles()[0].position().x(), 2.0 - 0.4, 0.01);
  EXPECT_EQ(sim2.robot().collisions(), 0u);
  // With patience it turns back along its loop after waiting that long.
  const Scenario patient = ScenarioText(
      "robots: [{start: [2.0, 1.0, 0.0]}]\n"
      "moving_obstacles:\n"
      "  - {name: cart, radius: 0.2, speed: 0.5, patience: 1.0, loop: [[1.0, 1.0], [3.0, 1.0]]}\n");
  Simulation sim3(patient, {});
  for (int i = 0; i < 220; ++i) sim3.Step();  // 1.2 s to the robot, 1 s waiting
  EXPECT_NEAR(sim3.moving_obstacles()[0].position().x(), 1.6, 0.01);
  for (int i = 0; i < 100; ++i) sim3.Step();  // then 1 s back
  EXPECT_LT(sim3.moving_obstacles()[0].position().x(), 1.6 - 0.3);
  EXPECT_EQ(sim3.robot().collisions(), 0u);
}

// A wide open 200 m street, walls far away, for motion statistics.
Scenario OpenStreet(const std::string& people) {
  const std::string world =
      WriteFile("open.yaml", "map: {resolution: 0.2, size: [200, 20]}\nrobot: {start: [1, 1, 0]}\n");
  return ParseScenario("world: " + world + "\nseed: 11\npeople:\n" + people, "street.yaml", ".");
}

TEST(Pedestrians, WalkAtTheirGaussianSpeedsWithBrownianSpread) {
  const Scenario s = OpenStreet(
      "  {area: [5, 2, 195, 18], mode: street, initial: [200, 200], max: 400, arrival_rate: 0, speed: [1.3, 0.2], "
      "brownian: 0.3, goal_period: [2, 5], goal_ahead: 10, spawn_clearance: 0}\n");
  Simulation sim(s, {});
  ASSERT_GT(sim.people().size(), 150u);
  // Preferred speeds: mean 1.3, std-dev 0.2.
  double sum = 0, sum2 = 0;
  for (const auto& p : sim.people()) {
    sum += p.speed;
    sum2 += p.speed * p.speed;
  }
  const double n = sim.people().size();
  EXPECT_NEAR(sum / n, 1.3, 0.05);
  EXPECT_NEAR(std::sqrt(sum2 / n - (sum / n) * (sum / n)), 0.2, 0.04);
  // Brownian motion: the step across the goal direction is pure noise of variance sigma^2 dt.
  double across2 = 0, along = 0;
  int samples = 0;
  for (int k = 0; k < 100; ++k) {
    std::vector<Person> before = sim.people();
    sim.Step();
    for (const Person& b : before) {
      for (const Person& a : sim.people()) {
        if (a.id != b.id || a.velocity.isZero()) continue;
        const Point2 dir = (b.goal - b.position).normalized();
        const Point2 step = a.position - b.position;
        const double cross = dir.x() * step.y() - dir.y() * step.x();
        across2 += cross * cross;
        along += step.dot(dir) / 0.01;
        ++samples;
      }
    }
  }
  ASSERT_GT(samples, 10000);
  EXPECT_NEAR(across2 / samples, 0.3 * 0.3 * 0.01, 0.3 * 0.3 * 0.01 * 0.1);
  EXPECT_NEAR(along / samples, 1.3, 0.05);  // they walk at their preferred speed towards the goal
}

TEST(Pedestrians, ArriveAsAPoissonProcessAndChangeGoalsEveryFewSeconds) {
  const Scenario s = OpenStreet(
      "  {area: [5, 2, 195, 18], mode: street, initial: [0, 0], max: 1000, arrival_rate: 0.5, speed: [1.3, 0.2], "
      "brownian: 0, goal_period: [2, 4], spawn_clearance: 0}\n");
  Simulation sim(s, {});
  const double seconds = 400;
  double person_seconds = 0;
  for (int i = 0; i < seconds * 100; ++i) {
    sim.Step();
    person_seconds += sim.people().size() * 0.01;
  }
  // Poisson: mean rate * T = 200, std-dev 14; allow 4 sigma.
  EXPECT_NEAR(sim.crowd()->arrivals(), 200, 57);
  // Each person redraws their goal every U(2, 4) s: 1 / 3 changes per person-second.
  EXPECT_NEAR(sim.crowd()->goal_changes() / person_seconds, 1.0 / 3.0, 0.03);
  // People cross the 190 m street (about 150 s at 1.3 m/s) and leave at its far end.
  EXPECT_GT(sim.crowd()->departures(), 50);
}

TEST(Pedestrians, StopShortOfRobotsAndAreSeenByTheLaser) {
  const Scenario s = ScenarioText(
      "robots: [{start: [2.0, 2.0, 0.0]}]\n"
      "people: {area: [0.5, 0.5, 3.5, 3.5], mode: room, initial: [6, 6], max: 6, arrival_rate: 0, brownian: 0.05, "
      "spawn_clearance: 0.3}\n");
  Simulation sim(s, {});
  int seen = 0;
  for (int i = 0; i < 3000; ++i) {
    const auto out = sim.Step();
    for (const auto& p : sim.people()) {
      ASSERT_GE(Distance(p.position, {2.0, 2.0}), 0.2 + 0.25 - 1e-9);  // never inside the robot
    }
    if (out.robots[0].scan) {
      for (float r : *out.robots[0].scan) seen += r < 1.0f;  // walls are >= 1.5 m away
    }
  }
  EXPECT_GT(seen, 0);
  EXPECT_EQ(sim.robot().collisions(), 0u);  // the robot never moved
}

// The people sensor reports each person in the robot's frame with the velocity they walk with,
// within its range and field of view, at its rate; a robot without one reports none.
TEST(Pedestrians, ThePeopleSensorReportsEveryoneInRangeInTheRobotsFrame) {
  const Scenario s = ScenarioText(
      "robots:\n"
      "  - {name: a, start: [2.0, 2.0, 1.0], sensors: [{type: people, range_max: 1.2, fov_deg: 180, rate_hz: 5}]}\n"
      "  - {name: b, start: [3.0, 3.0, 0.0], sensors: [{type: laser}]}\n"
      "people: {area: [0.5, 0.5, 3.5, 3.5], mode: room, initial: [8, 8], max: 8, arrival_rate: 0, brownian: 0.05, "
      "spawn_clearance: 0.3}\n");
  Simulation sim(s, {});
  int readings = 0, reported = 0;
  for (int i = 0; i < 1000; ++i) {
    const auto out = sim.Step();
    EXPECT_FALSE(out.robots[1].people);
    if (!out.robots[0].people) continue;
    ++readings;
    const Pose2 robot = sim.robot(0).base().true_pose();
    size_t expected = 0;
    for (const Person& p : sim.people()) {
      const Point2 at = robot.inverse() * p.position;
      if (at.norm() <= 1.2 && at.x() >= 0.0) ++expected;
    }
    ASSERT_EQ(out.robots[0].people->size(), expected) << "at t=" << sim.now();
    for (const PersonReading& r : *out.robots[0].people) {
      const auto truth =
          std::find_if(sim.people().begin(), sim.people().end(), [&](const Person& p) { return p.id == r.id; });
      ASSERT_NE(truth, sim.people().end());
      EXPECT_LT(Distance(robot * r.position, truth->position), 1e-9);
      const Point2 v = truth->velocity.isZero() ? Point2::Zero() : WalkingVelocity(*truth);
      EXPECT_LT((Rotate(r.velocity, robot.theta) - v).norm(), 1e-9);
      ++reported;
    }
  }
  EXPECT_NEAR(readings, 50, 1);  // 5 Hz for 10 s
  EXPECT_GT(reported, 0);
  EXPECT_THROW(ScenarioText("robots: [{start: [2, 2, 0], sensors: [{type: people, fov_deg: 400}]}]\n"), Error);
}

TEST(Scenarios, ShippedScenariosLoad) {
  for (const char* name : {"warehouse_run1", "warehouse_run2", "office", "street", "warehouse_fleet"}) {
    SCOPED_TRACE(name);
    const Scenario s = LoadScenarioFile(std::string(NAVD_SOURCE_DIR) + "/worlds/scenarios/" + name + ".yaml");
    EXPECT_FALSE(s.robots.empty());
    for (const Point2& t : s.targets) EXPECT_FALSE(s.truth.DiscHitsObstacle(t, 0.3)) << FormatPoint(t);
  }
  const Scenario run2 = LoadScenarioFile(std::string(NAVD_SOURCE_DIR) + "/worlds/scenarios/warehouse_run2.yaml");
  EXPECT_EQ(run2.targets.size(), 11u);
  EXPECT_EQ(run2.moving_obstacles.size(), 3u);
  const Scenario office = LoadScenarioFile(std::string(NAVD_SOURCE_DIR) + "/worlds/scenarios/office.yaml");
  EXPECT_EQ(office.hidden_obstacles, 15);
  int differ = 0;  // the hidden obstacles are in the truth, not in the robot's map
  for (size_t i = 0; i < office.truth.cells().size(); ++i)
    differ += office.truth.cells()[i] != office.world.map.cells()[i];
  EXPECT_GT(differ, 15);
}

void ExpectScenarioError(const std::string& text, const std::string& expected) {
  try {
    ScenarioText(text);
    FAIL() << "accepted: " << text;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("test.yaml:"), std::string::npos) << "no file:line in " << e.what();
  }
}

TEST(Scenarios, BadInputNamesFileLineAndField) {
  ExpectScenarioError("robots: [{start: [0.05, 2.0, 0.0]}]\n", "field 'robots[0].start' puts the robot inside");
  ExpectScenarioError("robots: [{start: [2, 2], sensors: [{type: radar}]}]\n",
                      "'robots[0].sensors[0].type' is not a known sensor type 'radar'");
  ExpectScenarioError("robots: [{start: [2, 2], sensors: [{type: laser, rate_hz: -10}]}]\n",
                      "'robots[0].sensors[0].rate_hz' must be positive");
  ExpectScenarioError("robots:\n  - {name: a, start: [1, 1]}\n  - {start: [2, 2]}\n", "'robots[1].name' is required");
  ExpectScenarioError("robots: [{start: [2, 2], drive: hovercraft}]\n",
                      "'robots[0].drive' must be diff_drive, omni or unicycle");
  ExpectScenarioError("moving_obstacles: [{loop: [[0.5, 0.5], [5, 0.5]]}]\n", "runs into a wall");
  ExpectScenarioError("people: {mode: street}\n", "'people.area' is missing");
  ExpectScenarioError("robotz: []\n", "'robotz' is not a known field");
  try {
    ParseScenario("seed: 1\n", "test.yaml", ".");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'world' is missing"), std::string::npos) << e.what();
  }
}

TEST(Worlds, PolygonWorldsRasteriseAndRejectSelfIntersection) {
  const World w = ParseWorld(
      "map:\n  resolution: 0.05\n  size: [10, 10]\n"
      "  boundary: [[0.5, 0.5], [9.5, 0.5], [9.5, 9.5], [0.5, 9.5]]\n"
      "  polygons:\n    - [[4, 4], [6, 4], [5, 6]]\n"
      "robot: {start: [2, 2, 0]}\n",
      "poly.yaml", ".");
  EXPECT_TRUE(w.map.IsOccupied(w.map.CellOf({0.2, 5})));  // outside the boundary
  EXPECT_FALSE(w.map.IsOccupied(w.map.CellOf({2, 5})));   // inside it
  EXPECT_TRUE(w.map.IsOccupied(w.map.CellOf({5, 4.5})));  // inside the triangle
  EXPECT_FALSE(w.map.IsOccupied(w.map.CellOf({4.2, 5.8})));
  EXPECT_NEAR(RayCaster(w.map).Cast({2, 4.1}, 0.0, 10), 2.0, 0.05);
  try {
    ParseWorld("map:\n  size: [10, 10]\n  polygons:\n    - [[1, 1], [3, 3], [3, 1], [1, 3]]\nrobot: {start: [5, 5]}\n",
               "bow.yaml", ".");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bow.yaml:4: field 'map.polygons[0]' is not a simple closed curve"),
              std::string::npos)
        << e.what();
  }
}

TEST(Determinism, SameScenarioSeedAndCommandsGiveBitIdenticalTruth) {
  auto run = [](uint64_t seed) {
    Scenario s = LoadScenarioFile(std::string(NAVD_SOURCE_DIR) + "/worlds/scenarios/warehouse_fleet.yaml");
    s.moving_obstacles.push_back({"cart", 0.2, 0.3, {{2.2, 4.2}, {5.6, 4.2}}});
    SimulationOptions o;
    o.seed = seed;
    Simulation sim(s, o);
    std::vector<double> trace;
    for (int i = 0; i < 2000; ++i) {
      sim.Command(0, {0.3, 0.0, 0.1 * std::sin(i * 0.01)});
      sim.Command(1, {0.2, 0.0, -0.2});
      const auto out = sim.Step();
      for (const auto& r : sim.robots()) {
        trace.insert(trace.end(), {r->base().true_pose().x, r->base().true_pose().y, r->base().odom_pose().theta});
      }
      for (const auto& p : sim.people()) trace.insert(trace.end(), {p.position.x(), p.position.y()});
      if (out.robots[0].scan) trace.push_back((*out.robots[0].scan)[100]);
    }
    return trace;
  };
  const auto a = run(5), b = run(5), c = run(6);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(double)));
  EXPECT_NE(a, c);
}

TEST(CarmenRecorder, RoundTripsThroughTheLogReader) {
  Simulation sim(DefaultWorld(), {});
  const std::string path = TempDir() + "/run.log";
  std::vector<std::vector<float>> scans;
  std::vector<Pose2> truths;
  {
    CarmenRecorder rec(path, "test");
    const auto& r = sim.robot();
    for (int i = 0; i < 500; ++i) {
      sim.Command(0, {0.2, 0.0, 0.1});
      const auto out = sim.Step();
      const auto& b = r.base();
      if (out.robots[0].scan) {
        rec.Laser(sim.now(), r.laser()->description(), r.laser()->angle_min(), r.laser()->increment(),
                  *out.robots[0].scan, b.true_pose(), b.odom_pose(), b.odom_twist().vx, b.odom_twist().omega);
        scans.push_back(*out.robots[0].scan);
      }
      if (out.robots[0].odom) rec.Odometry(sim.now(), b.odom_pose(), b.odom_twist().vx, b.odom_twist().omega);
      if (out.truth) {
        rec.Truth(sim.now(), b.true_pose(), b.odom_pose());
        truths.push_back(b.true_pose());
      }
    }
    EXPECT_FALSE(std::filesystem::exists(path));  // not under its name until closed
    rec.Close();
  }
  const CarmenLog log = ReadCarmenLog(path, /*strict=*/true);
  ASSERT_EQ(log.scans.size(), scans.size());
  ASSERT_EQ(log.scans.size(), 50u);
  EXPECT_EQ(log.odometry.size(), 250u);
  ASSERT_EQ(log.truth.size(), truths.size());
  const auto& laser = *sim.robot().laser();
  for (size_t i = 0; i < scans.size(); ++i) {
    ASSERT_EQ(log.scans[i].ranges.size(), 683u);
    EXPECT_NEAR(log.scans[i].angle_min, laser.angle_min(), 1e-6);
    EXPECT_NEAR(log.scans[i].angle_increment, laser.increment(), 1e-8);
    EXPECT_NEAR(log.scans[i].range_max, 4.0, 1e-9);
    for (size_t k = 0; k < scans[i].size(); ++k) EXPECT_NEAR(log.scans[i].ranges[k], scans[i][k], 0.0006);
    EXPECT_NEAR(log.scans[i].timestamp, 0.01 + 0.1 * i, 1e-6);  // the first scan comes with the first step
  }
  for (size_t i = 0; i < truths.size(); ++i) {
    EXPECT_NEAR(log.truth[i].pose.x, truths[i].x, 1e-6);
    EXPECT_NEAR(log.truth[i].pose.theta, truths[i].theta, 1e-6);
  }
}

TEST(LockstepGate, HoldsTheSimulationAtAControllersNextTickUntilItReportsTheNext) {
  LockstepGate gate(2, 5.0);
  gate.Report(0, 1.0e9);  // robot 0's controller is far ahead
  gate.Report(1, 1.05);
  EXPECT_TRUE(gate.WaitUntilAllowed(1.04).empty());
  // At 1.05 the controller has not finished that tick: the step waits until it reports the next.
  std::atomic<bool> released{false};
  std::thread step([&] {
    EXPECT_TRUE(gate.WaitUntilAllowed(1.05).empty());
    released = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(released);
  gate.Report(1, 1.10);
  step.join();
  EXPECT_TRUE(released);
}

TEST(LockstepGate, TheSimulationWaitsAtItsStartForEveryControllersFirstReport) {
  LockstepGate gate(1, 5.0);
  EXPECT_TRUE(gate.holding());
  std::atomic<bool> released{false};
  std::thread step([&] {
    EXPECT_TRUE(gate.WaitUntilAllowed(0.0).empty());
    released = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(released);  // navd still starting: time stays at 0
  gate.Report(0, 0.05);
  step.join();
  EXPECT_TRUE(released);
}

TEST(LockstepGate, AControllerThatNeverReportsIsReleasedAfterTheTimeout) {
  LockstepGate gate(2, 0.1);  // two robots, neither with a navd
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(gate.WaitUntilAllowed(0.0), (std::vector<size_t>{0, 1}));
  EXPECT_GE(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 0.09);
  EXPECT_FALSE(gate.holding());
  EXPECT_TRUE(gate.WaitUntilAllowed(100.0).empty());  // stepping on without them
}

// navsim repeats rt/clock while it waits: a navd whose reader matched after the first sample (best
// effort, lost) hears a later one, ticks and reports, and the run goes on without the timeout.
TEST(LockstepGate, WhileHeldTheWaitRepeatsItsCallbackUntilTheControllerAnswers) {
  LockstepGate gate(1, 5.0);
  int repeats = 0;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_TRUE(gate.WaitUntilAllowed(0.0,
                                    [&] {
                                      if (++repeats == 3) gate.Report(0, 0.05);  // the third clock got through
                                    })
                  .empty());
  EXPECT_EQ(repeats, 3);
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(waited, 3 * LockstepGate::kRepeatPeriod - 0.01);
  EXPECT_LT(waited, 2.0);  // well before the timeout
  EXPECT_TRUE(gate.holding());
  // A controller that never answers is still released at the timeout, the callback repeating until then.
  LockstepGate silent(1, 0.3);
  repeats = 0;
  EXPECT_EQ(silent.WaitUntilAllowed(0.0, [&] { ++repeats; }), std::vector<size_t>{0});
  EXPECT_GE(repeats, 3);
  EXPECT_LE(repeats, 6);
}

TEST(LockstepGate, ASilentControllerIsReleasedAfterTheTimeoutAndHeldAgainWhenItReports) {
  LockstepGate gate(1, 0.1);
  gate.Report(0, 2.0);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(gate.WaitUntilAllowed(2.0), std::vector<size_t>{0});
  EXPECT_GE(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 0.09);
  EXPECT_FALSE(gate.holding());
  EXPECT_TRUE(gate.WaitUntilAllowed(50.0).empty());  // stepping on without it
  gate.Report(0, 60.0);                              // a restarted navd
  EXPECT_TRUE(gate.holding());
  EXPECT_EQ(gate.WaitUntilAllowed(60.0), std::vector<size_t>{0});
}

}  // namespace
}  // namespace navd::sim
