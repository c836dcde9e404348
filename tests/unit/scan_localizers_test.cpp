// The scan-to-map fit and the EKF of seed 002 against navsim's robot and laser: the fit pulls a
// displaced pose back onto the walls, the EKF corrects seed 000's validation case and tracks a
// drive while odometry drifts, and bad input never reaches its state.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "services/common/error.h"
#include "services/common/ray_caster.h"
#include "services/common/world.h"
#include "services/localization/ekf_localizer.h"
#include "services/localization/histogram_localizer.h"
#include "services/localization/localizer_selector.h"
#include "services/localization/odometric_calibration.h"
#include "services/localization/odometry_localizer.h"
#include "services/localization/scan_odometry_pairing.h"
#include "services/localization/scan_points.h"
#include "services/localization/scan_to_map_fit.h"
#include "services/localization/wheel_odometry.h"
#include "simulator/laser_scanner.h"
#include "simulator/scenario.h"
#include "tests/support/simulated_drive.h"

namespace navd::localization {
namespace {

sim::SimulationOptions Seeded(uint64_t seed) {
  sim::SimulationOptions o;
  o.seed = seed;
  return o;
}

World WithStart(const Pose2& start) {
  World w = DefaultWorld();
  w.start = start;
  return w;
}

TEST(ScanOdometryPairing, AScanWaitsForTheOdometryOfItsInstantThenGetsItFirst) {
  using localization::OdometryReading;
  using localization::ScanOdometryPairing;
  using std::chrono::milliseconds;
  const ScanOdometryPairing::WallClock::time_point start{};
  ScanOdometryPairing pairing(milliseconds(50));
  const OdometryReading before{{1.0, 0.0, 0.0}, Eigen::Matrix3d::Zero(), 1.0};
  // The scan at 1.5 s came before the odometry of 1.5 s: it waits, and a newer scan taking its
  // place does not start the wait again; after 50 ms it goes on without.
  EXPECT_TRUE(pairing.Waits(1.5, before, start));
  EXPECT_TRUE(pairing.Waits(1.6, before, start + milliseconds(40)));
  EXPECT_FALSE(pairing.Waits(1.6, before, start + milliseconds(60)));
  // No odometry at all, or odometry already past the scan: no wait.
  EXPECT_FALSE(pairing.Waits(1.5, std::nullopt, start));
  const OdometryReading after{{2.0, 0.0, 0.4}, Eigen::Matrix3d::Identity(), 2.0};
  EXPECT_FALSE(pairing.Waits(1.5, after, start));
  // The history has taken out a jump of 10 m: the reading at the scan is carried back from the
  // newest by the motion between them, not read off the history's frame.
  auto history = [](double t) { return std::optional<Pose2>(Pose2{t - 10.0, 0.0, 0.4 * (t - 1.0)}); };
  const std::vector<OdometryReading> first = pairing.Readings(after, 1.5, history);
  ASSERT_EQ(first.size(), 2u);
  EXPECT_DOUBLE_EQ(first[0].stamp, 1.5);
  EXPECT_NEAR(first[0].pose.x, 1.5, 1e-9);
  EXPECT_NEAR(first[0].pose.y, 0.0, 1e-9);
  EXPECT_NEAR(first[0].pose.theta, 0.2, 1e-9);
  EXPECT_EQ(first[0].covariance, Eigen::Matrix3d::Identity());
  EXPECT_DOUBLE_EQ(first[1].stamp, 2.0);
  // Once a later reading went in, an older instant never follows it (out of order), and without
  // a scan only the newest goes in.
  EXPECT_EQ(pairing.Readings(after, 1.8, history).size(), 1u);
  EXPECT_EQ(pairing.Readings(after, std::nullopt, history).size(), 1u);
  EXPECT_TRUE(pairing.Readings(std::nullopt, 2.5, history).empty());
  // The odometry's clock went back (a replay started again): scans are paired again.
  const OdometryReading restarted{{0.5, 0.0, 0.0}, Eigen::Matrix3d::Zero(), 1.2};
  EXPECT_EQ(pairing.Readings(restarted, 1.1, history).size(), 2u);
}

// A scanner's error codes (a few millimetres, reported as ranges), NaN and -inf give the localisers
// no beam, even when the scan's range_min lets them through; +inf is a no-return.
TEST(ScanPoints, ReadingsThatSayNothingGiveNoBeam) {
  ScanReading scan;
  const float inf = std::numeric_limits<float>::infinity();
  scan.ranges = {0.004f, 2.0f, 0.019f, 3.0f, std::numeric_limits<float>::quiet_NaN(), -inf, inf};
  scan.angle_min = -0.1;
  scan.angle_increment = 0.05;
  scan.range_min = 0.0;
  scan.range_max = 30.0;
  const std::vector<ScanBeam> beams = SampleBeams(scan, 0);
  ASSERT_EQ(beams.size(), 3u);
  EXPECT_TRUE(beams[0].hit);
  EXPECT_NEAR(beams[0].angle, -0.05, 1e-12);
  EXPECT_TRUE(beams[1].hit);
  EXPECT_FALSE(beams[2].hit);  // +inf
  EXPECT_EQ(beams[2].range, 30.0);
  EXPECT_EQ(ScanEndPoints(scan, 0).size(), 2u);
}

// One noisy scan of the default world from `truth`, fitted from poses displaced by up to 0.2 m
// and 0.12 rad (seed 000's validation offset is 0.2 m and 0.14 rad): every fit lands within a
// centimetre and 5 mrad of the truth.
TEST(ScanToMapFit, PullsADisplacedPoseBackOntoTheWalls) {
  const World world = DefaultWorld();
  const LikelihoodField field(world.map);
  const ScanToMapFit fit(field);
  std::mt19937_64 rng(5);
  const Pose2 truths[3] = {{2.45, 4.23, M_PI}, world.start, {8.5, 8.4, 2.0}};
  for (const Pose2& truth : truths) {
    const auto points = ScanEndPoints(SimulatedScan(world, truth, rng), 120);
    for (const Pose2& offset : {Pose2{-0.2, -0.03, -0.12}, Pose2{0.15, 0.1, 0.08}, Pose2{0.0, -0.2, 0.05}}) {
      const Pose2 start{truth.x + offset.x, truth.y + offset.y, truth.theta + offset.theta};
      const ScanToMapFitResult r = fit.Fit(points, start);
      ASSERT_TRUE(r.ok);
      EXPECT_LT(std::hypot(r.pose.x - truth.x, r.pose.y - truth.y), 0.01)
          << "truth (" << truth.x << ", " << truth.y << "), found (" << r.pose.x << ", " << r.pose.y << ")";
      EXPECT_LT(std::abs(NormalizeAngle(r.pose.theta - truth.theta)), 0.005);
      EXPECT_LT(r.rms, 0.03);
      EXPECT_GT(r.inliers, 100);
    }
  }
}

// Street seed 150 in navd: escapes among walkers took the robot back to the street's open end; the
// laser read the map's edge there as a wall, half the beams missed the map, and navd declared the
// pose lost and never found it again in the featureless street. Out of the open end the laser sees
// nothing, and a scan there fits the map at the true pose.
TEST(LikelihoodField, AScanAtTheStreetsOpenEndFitsTheMap) {
  const World street = LoadWorldFile(std::string(NAVD_SOURCE_DIR) + "/worlds/street.yaml");
  const LikelihoodField field(street.map);
  std::mt19937_64 rng(3);
  for (const Pose2& truth : {Pose2{0.42, 2.58, -2.89}, Pose2{99.5, 4.0, 0.0}, Pose2{0.4, 7.5, M_PI}}) {
    const auto points = ScanEndPoints(SimulatedScan(street, truth, rng), 90);
    EXPECT_GT(points.size(), 20u);
    EXPECT_GT(field.Agreement(truth, points), 0.9) << truth.x << ", " << truth.y;
  }
}

// Seed 000's validation case (section 4.3, with its moving obstacle in view), ten runs, with the
// EKF: within 0.02 m and 0.01 rad.
TEST(Ekf, CorrectsTheSeedZeroValidationCase) {
  for (int run = 0; run < 10; ++run) {
    const sim::Scenario scenario = SeedZeroValidationScenario();
    sim::Simulation s(scenario, Seeded(500 + run));
    EkfLocalizer ekf(scenario.world.map);
    const Errors e = RunSeedZeroValidation(s, ekf);
    std::printf("EKF validation run %d: worst error standing still %.4f m, %.4f rad\n", run, e.position, e.heading);
    EXPECT_LT(e.position, 0.02) << "run " << run;
    EXPECT_LT(e.heading, 0.01) << "run " << run;
  }
}

// Seed 002's claim, in navsim: with odometry 3% long and turning 4% too far (a mis-measured wheel
// radius and wheel base) on top of six times navsim's default slip, the EKF keeps the pose where
// dead reckoning drifts away.
TEST(Ekf, TracksADriveWhileOdometryDrifts) {
  World world = DefaultWorld();
  world.robot.encoder_noise = 0.03;
  sim::Simulation s(world, {});
  EkfLocalizer ekf(world.map, {}, world.start, Eigen::Matrix3d::Identity() * 1e-4);
  ekf.AddOdometry({s.robot().base().odom_pose(), Eigen::Matrix3d::Zero(), 0.0});
  const Errors e = Drive(s, ekf, 50.0, UpTheCorridorAndBack, 50.0, {0.03, 0.04});
  // Dead reckoning with the same bias, for comparison.
  sim::Simulation again(world, {});
  OdometryLocalizer odometry(world.start);
  Drive(again, odometry, 50.0, UpTheCorridorAndBack, 50.0, {0.03, 0.04});
  const Pose2 odom = odometry.Estimate().pose;
  const Pose2 truth = again.robot().base().true_pose();
  const double odometry_error = std::hypot(odom.x - truth.x, odom.y - truth.y);
  std::printf("EKF drive: worst %.3f m / %.3f rad, mean %.4f m / %.4f rad; odometry error at the end %.3f m\n",
              e.position, e.heading, e.mean_position, e.mean_heading, odometry_error);
  EXPECT_LT(e.position, 0.08);
  EXPECT_LT(e.heading, 0.04);
  EXPECT_LT(e.mean_position, 0.03);
  EXPECT_GT(odometry_error, 3 * e.mean_position);
  EXPECT_EQ(ekf.rejected_in_a_row(), 0);
}

TEST(Ekf, IgnoresMalformedInputAndRefusesMatchesOutsideItsGate) {
  const World world = DefaultWorld();
  EkfOptions o;
  o.update_min_distance = o.update_min_angle = 0.0;  // correct at every scan, standing still
  EkfLocalizer ekf(world.map, o, world.start, Eigen::Matrix3d::Identity() * 1e-4);
  ekf.AddOdometry({{0, 0, 0}, Eigen::Matrix3d::Zero(), 0.0});
  ekf.AddOdometry({{NAN, 0, 0}, Eigen::Matrix3d::Zero(), 0.1});
  ScanReading bad;
  EXPECT_FALSE(ekf.AddScan(bad));  // no ranges
  bad.ranges.assign(683, NAN);
  bad.angle_increment = 0.006;
  bad.range_max = 4.0;
  EXPECT_FALSE(ekf.AddScan(bad));  // no usable beams
  PoseEstimate e = ekf.Estimate();
  EXPECT_TRUE(e.pose.finite());
  EXPECT_TRUE(e.covariance.allFinite());
  EXPECT_NEAR(e.pose.x, world.start.x, 1e-9);

  // Scans taken 0.3 m ahead of where a confident filter (1 cm) is: the fit finds that place, the
  // gate refuses it, the estimate stays...
  std::mt19937_64 rng(1);
  const Pose2 ahead = world.start * Pose2{0.3, 0.0, 0.0};
  ScanReading far;
  for (int i = 1; i < o.reanchor_after; ++i) {
    ekf.AddOdometry({{0, 0, 0}, Eigen::Matrix3d::Zero(), 0.1 * i});
    far = SimulatedScan(world, ahead, rng);
    far.stamp = 0.1 * i;
    EXPECT_FALSE(ekf.AddScan(far)) << i;
    EXPECT_NEAR(ekf.Estimate().pose.x, world.start.x, 1e-9);
  }
  // ... until the refusals have gone on long enough: then the match wins and the filter re-anchors.
  ekf.AddOdometry({{0, 0, 0}, Eigen::Matrix3d::Zero(), 1.0});
  far.stamp = 1.0;
  EXPECT_TRUE(ekf.AddScan(far));
  e = ekf.Estimate();
  EXPECT_LT(std::hypot(e.pose.x - ahead.x, e.pose.y - ahead.y), 0.02);
}

// Seed 000's own validation case for its odometric calibration (section 5.3), with the moving
// obstacle crossing the laser's view, ten runs. The seed reached about 0.05 m and 0.03 rad; the
// issue asks for 0.02 m and 0.01 rad.
TEST(OdometricCalibration, CorrectsTheSeedZeroValidationCaseWithAMovingObstacleInView) {
  for (int run = 0; run < 10; ++run) {
    const sim::Scenario scenario = SeedZeroValidationScenario();
    sim::Simulation s(scenario, Seeded(700 + run));
    OdometricCalibrationLocalizer calibration(scenario.world.map);
    const Errors e = RunSeedZeroValidation(s, calibration);
    std::printf("calibration validation run %d: worst error standing still %.4f m, %.4f rad, %d searches\n", run,
                e.position, e.heading, calibration.searches());
    EXPECT_LT(e.position, 0.02) << "run " << run;
    EXPECT_LT(e.heading, 0.01) << "run " << run;
    EXPECT_GE(calibration.searches(), 1);
  }
}

// With odometry 3% long and turning 4% too far, calibration keeps the pose on a drive (up the
// corridor, a half turn on the spot slow enough to stay under T_dv, and back) where dead reckoning
// drifts by most of a metre.
TEST(OdometricCalibration, KeepsThePoseWhileOdometryDrifts) {
  World world = DefaultWorld();
  world.robot.encoder_noise = 0.03;
  sim::Simulation s(world, {});
  OdometricCalibrationLocalizer calibration(world.map, {}, world.start);
  calibration.AddOdometry({s.robot().base().odom_pose(), Eigen::Matrix3d::Zero(), 0.0});
  const Errors e = Drive(s, calibration, 56.0,
                         [](double t) {
                           if (t < 20) return Twist2{0.3, 0.0};
                           if (t < 36) return Twist2{0.0, M_PI / 16};  // 0.065 m/s of wheel speed difference < T_dv
                           return Twist2{0.3, 0.0};
                         },
                         56.0, {0.03, 0.04});
  std::printf("calibration drive: worst %.3f m / %.3f rad, mean %.4f m / %.4f rad, %d searches\n", e.position,
              e.heading, e.mean_position, e.mean_heading, calibration.searches());
  EXPECT_LT(e.position, 0.06);
  EXPECT_LT(e.heading, 0.04);
  EXPECT_LT(e.mean_position, 0.02);
  EXPECT_GE(calibration.searches(), 5);
}

// Book chapter 3's delta: one action moves the belief to the intended neighbour with p = 2/3 and
// to each of the two beside it with 1/6. A certain belief moved one cell along x shows exactly that
// along x.
TEST(Histogram, OneCellOfMotionSpreadsTheBeliefAsTheChaptersDelta) {
  const World world = DefaultWorld();
  HistogramLocalizer h(world.map);
  h.AddOdometry({{0, 0, 0}, Eigen::Matrix3d::Zero(), 0.0});
  const Pose2 at{4.05, 5.05, 0.0};  // a cell centre in the open middle of the room
  h.SetPose(at, Eigen::Matrix3d::Zero());
  const int c = h.ColumnOf(at.x);
  EXPECT_NEAR(h.MarginalX()[c], 1.0, 1e-6);
  h.AddOdometry({{0.1, 0, 0}, Eigen::Matrix3d::Zero(), 0.1});
  const std::vector<double> m = h.MarginalX();
  EXPECT_NEAR(m[c], 1.0 / 6, 1e-5);
  EXPECT_NEAR(m[c + 1], 2.0 / 3, 1e-5);
  EXPECT_NEAR(m[c + 2], 1.0 / 6, 1e-5);
  EXPECT_NEAR(h.Estimate().pose.x, at.x + 0.1, 1e-6);
}

// With no prior at all (uniform over the free space), the histogram filter finds the robot in the
// rooms once it has looked around, as the particle filter does.
TEST(Histogram, FindsTheRobotWithNoPrior) {
  const Pose2 starts[3] = {{8.5, 8.4, M_PI}, {4.0, 5.0, 0.0}, {3.0, 2.6, M_PI / 2}};
  for (int run = 0; run < 3; ++run) {
    World world = WithStart(starts[run]);
    sim::Simulation s(world, Seeded(900 + run));
    HistogramLocalizer h(world.map);
    h.AddOdometry({s.robot().base().odom_pose(), Eigen::Matrix3d::Zero(), 0.0});
    const Errors e = Drive(
        s, h, 14.0,
        [](double t) {
          return Twist2{0.0, t < 12 ? 0.6 : 0.0};
        },
        1.0);
    std::printf("histogram global run %d: error %.3f m, %.3f rad\n", run, e.position, e.heading);
    EXPECT_LT(e.position, 0.1) << "run " << run;
    EXPECT_LT(e.heading, 0.1) << "run " << run;
  }
}

TEST(Histogram, RefusesMapsTooLargeForItsGrid) {
  OccupancyGrid big(4000, 4000, 0.05, {0, 0});
  try {
    HistogramLocalizer h(big);
    FAIL() << "a 200 x 200 m map at 0.1 m x 36 headings was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("max_states"), std::string::npos) << e.what();
  }
}

// A jump in the odometry (the odom frame reset, a glitch) is taken as no motion: the estimate stays
// where the robot was, and motion after it carries on from there.
TEST(LocalizerInput, OdometryJumpsCountAsNoMotion) {
  const World world = DefaultWorld();
  LocalizerSelector selector;
  selector.Add(std::make_unique<OdometryLocalizer>(world.start));
  selector.Add(std::make_unique<EkfLocalizer>(world.map, EkfOptions{}, world.start));
  selector.AddOdometry({{0, 0, 0}, Eigen::Matrix3d::Zero(), 0.0});
  selector.SetPose(world.start, Eigen::Matrix3d::Zero());
  for (int i = 1; i <= 10; ++i) selector.AddOdometry({{0.01 * i, 0, 0}, Eigen::Matrix3d::Zero(), 0.02 * i});
  const Pose2 before = selector.Estimate().pose;
  selector.AddOdometry({{5.1, -3.0, 1.0}, Eigen::Matrix3d::Zero(), 0.22});  // 6 m in 20 ms
  EXPECT_EQ(selector.odometry_jumps(), 1);
  for (const std::string method : {"odometry", "ekf"}) {
    selector.Select(method);
    EXPECT_NEAR(selector.Estimate().pose.x, before.x, 1e-9) << method;
    EXPECT_NEAR(selector.Estimate().pose.y, before.y, 1e-9) << method;
    EXPECT_NEAR(selector.Estimate().pose.theta, before.theta, 1e-9) << method;
  }
  // 10 cm forward in the new odom frame (heading 1.0 there) is 10 cm forward for the robot.
  selector.AddOdometry({{5.1 + 0.1 * std::cos(1.0), -3.0 + 0.1 * std::sin(1.0), 1.0}, Eigen::Matrix3d::Zero(), 0.5});
  EXPECT_EQ(selector.odometry_jumps(), 1);
  const Pose2 after = selector.Estimate().pose;
  EXPECT_NEAR(after.x, before.x + 0.1 * std::cos(before.theta), 1e-6);
  EXPECT_NEAR(after.y, before.y + 0.1 * std::sin(before.theta), 1e-6);
  // A fast but possible step (1 m in 0.5 s) is motion, not a jump.
  selector.AddOdometry({{5.1 + 1.1 * std::cos(1.0), -3.0 + 1.1 * std::sin(1.0), 1.0}, Eigen::Matrix3d::Zero(), 1.0});
  EXPECT_EQ(selector.odometry_jumps(), 1);
}

TEST(LocalizerInput, ScanGeometryMustAgreeWithItsBeamCount) {
  const double min = -2.0944, inc = 4.1888 / 682;
  EXPECT_EQ(ScanGeometryError(683, min, min + 682 * inc, inc), "");
  EXPECT_NE(ScanGeometryError(600, min, min + 682 * inc, inc).find("ranges has 600 beams"), std::string::npos);
  EXPECT_NE(ScanGeometryError(683, min, min + 682 * inc, 0.0).find("angle_increment"), std::string::npos);
  EXPECT_NE(ScanGeometryError(683, NAN, 1.0, inc).find("angle_min"), std::string::npos);
  EXPECT_NE(ScanGeometryError(0, 0, 0, 1).find("empty"), std::string::npos);
}

// Odometry from wheel encoders (book ch. 1, Eqs. 7-12): navsim's robot firmware integrates its
// encoder ticks; navd's WheelOdometry, given only the wheel angles of each step, gets the same pose
// for a differential drive and for the three-wheel omnidirectional base.
TEST(WheelOdometry, ReproducesTheRobotsOdometryFromItsWheelAngles) {
  for (const DriveType drive : {DriveType::kDiffDrive, DriveType::kOmni}) {
    World world = DefaultWorld();
    world.robot.drive = drive;
    sim::Simulation s(world, {});
    WheelOdometry odometry(world.robot);
    ASSERT_TRUE(odometry.AddWheelAngles(s.robot().base().wheel_angles(), 0.0));
    const Pose2 anchor = s.robot().base().odom_pose();
    OdometryReading last;
    for (int i = 0; i < 1500; ++i) {
      const double t = 0.01 * i;
      s.Command(0, {0.3, drive == DriveType::kOmni ? 0.15 : 0.0, t < 8 ? 0.4 : -0.3});
      s.Step();
      const auto reading = odometry.AddWheelAngles(s.robot().base().wheel_angles(), s.now());
      ASSERT_TRUE(reading);
      last = *reading;
    }
    const Pose2 expected = anchor.inverse() * s.robot().base().odom_pose();
    std::printf("%s: wheel odometry (%.4f, %.4f, %.4f), firmware (%.4f, %.4f, %.4f)\n", DriveTypeName(drive),
                last.pose.x, last.pose.y, last.pose.theta, expected.x, expected.y, expected.theta);
    EXPECT_NEAR(last.pose.x, expected.x, 1e-9);
    EXPECT_NEAR(last.pose.y, expected.y, 1e-9);
    EXPECT_NEAR(last.pose.theta, expected.theta, 1e-9);
    EXPECT_GT(std::hypot(last.pose.x, last.pose.y), 0.5);  // it went somewhere
    EXPECT_GT(last.covariance(0, 0), 0.0);
  }
  // Wrong wheel counts and non-finite angles are refused, not integrated.
  WheelOdometry odometry(DefaultWorld().robot);
  EXPECT_FALSE(odometry.AddWheelAngles({1.0, 2.0, 3.0}, 0.0));
  EXPECT_FALSE(odometry.AddWheelAngles({NAN, 2.0}, 0.0));
}

}  // namespace
}  // namespace navd::localization
