// The odometry's systematic error: the replay's noise model giving it (OdometryNoise's S and D)
// and SLAM learning it back (OdometryBias).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>

#include "services/common/error.h"
#include "services/common/odometry_noise.h"
#include "services/mapping/odometry_bias.h"

namespace navd {
namespace {

TEST(OdometryNoise, ParsesTwoOrFourFieldsAndRefusesTheRest) {
  const OdometryNoise two = ParseOdometryNoise("0.05,0.035");
  EXPECT_DOUBLE_EQ(two.translation, 0.05);
  EXPECT_DOUBLE_EQ(two.rotation_per_metre, 0.035);
  EXPECT_DOUBLE_EQ(two.scale_error, 0.0);
  EXPECT_DOUBLE_EQ(two.drift, 0.0);
  const OdometryNoise four = ParseOdometryNoise("0.05,0.035,-0.03,0.02");
  EXPECT_DOUBLE_EQ(four.scale_error, -0.03);
  EXPECT_DOUBLE_EQ(four.drift, 0.02);
  for (const char* bad : {"0.05", "0.05,0.035,0.03", "0.05,0.035x", "0.05,0.035,0.03,0.02,1", "0.05,0.035,-1,0",
                          "-0.05,0.035", "0.05,nan,0,0", "0.05,0.035,0,inf", ""}) {
    try {
      ParseOdometryNoise(bad, "--odom-noise");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("--odom-noise"), std::string::npos) << e.what();
    }
  }
}

TEST(OdometryNoise, ASystematicErrorScalesEveryStepAndTurnsItByTheDistance) {
  OdometryNoise noise;
  noise.translation = noise.rotation_per_metre = 0.0;
  noise.scale_error = 0.1;
  noise.drift = 0.05;
  OdometryCorruptor corruptor(noise, 1);
  Pose2 last = corruptor.Next({2.0, 1.0, 0.3});
  for (int k = 1; k <= 5; ++k) {
    const Pose2 odometry = corruptor.Next({2.0 + 2.0 * k * std::cos(0.3), 1.0 + 2.0 * k * std::sin(0.3), 0.3});
    const Pose2 step = last.inverse() * odometry;
    EXPECT_NEAR(step.x, 2.2, 1e-9);
    EXPECT_NEAR(step.y, 0.0, 1e-9);
    EXPECT_NEAR(step.theta, 0.1, 1e-9);
    last = odometry;
  }
}

using mapping::OdometryBias;
using mapping::OdometryBiasOptions;
using mapping::RobotOdometryBias;

// Steps of a robot whose odometry reads `scale` times the true translation and turns
// `drift` rad per metre and `turn_error` of each turn too far; the "matched" step is the true one,
// with a little matching noise.
struct BiasedRobot {
  double scale = 1.03, drift = 0.02, turn_error = 0.04;
  std::mt19937 rng{7};
  std::normal_distribution<double> noise{0.0, 1.0};
  // A true step and the odometry's reading of it.
  std::pair<Pose2, Pose2> Step() {
    const double travel = 0.5 + 0.5 * std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    const double turn = 0.4 * noise(rng);
    const Pose2 truth{travel, 0.0, turn};
    const Pose2 odometry{scale * travel, 0.0, turn + turn_error * turn + drift * scale * travel};
    const Pose2 matched{truth.x + 0.005 * noise(rng), 0.005 * noise(rng), truth.theta + 0.002 * noise(rng)};
    return {odometry, matched};
  }
  // `steps` steps taught to `bias`, the walls having fixed the parts said.
  void Drive(OdometryBias& bias, int steps, bool translation_fixed = true, bool heading_fixed = true) {
    for (int k = 0; k < steps; ++k) {
      const auto [odometry, matched] = Step();
      bias.Observe(odometry, matched, translation_fixed, heading_fixed);
    }
  }
};

TEST(OdometryBiasLearning, OffByDefaultItLearnsNothing) {
  OdometryBias bias;
  BiasedRobot robot;
  robot.Drive(bias, 100);
  const Pose2 step{1.0, 0.1, 0.2};
  const Pose2 corrected = bias.Correct(step);
  EXPECT_DOUBLE_EQ(corrected.x, step.x);
  EXPECT_DOUBLE_EQ(corrected.y, step.y);
  EXPECT_DOUBLE_EQ(corrected.theta, step.theta);
}

TEST(OdometryBiasLearning, LearnsTheScaleTheDriftAndTheTurnErrorAndTakesThemOut) {
  OdometryBias bias(RobotOdometryBias());
  BiasedRobot robot;
  robot.Drive(bias, 300);
  // The odometry's turn, (1 + 0.04) of the true one, is corrected by -0.04 / 1.04 of itself, and
  // its drift per metre read by 1 - 0.04 / 1.04 of the 0.02; the prior ("no error") holds both a
  // little back while the steps driven are few.
  EXPECT_NEAR(bias.scale(), 1.0 / 1.03, 0.003);
  EXPECT_NEAR(bias.drift(), -0.02 / 1.04, 0.005);
  EXPECT_NEAR(bias.turn_error(), -0.04 / 1.04, 0.01);
  // A step read by that odometry comes out about as the robot moved.
  const auto [odometry, matched] = robot.Step();
  const Pose2 corrected = bias.Correct(odometry);
  EXPECT_NEAR(corrected.x, matched.x, 0.02);
  EXPECT_NEAR(corrected.theta, matched.theta, 0.01);
}

TEST(OdometryBiasLearning, LearnsTheTurnErrorFromTurnsOnTheSpot) {
  OdometryBias bias(RobotOdometryBias());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> turn(0.2, 1.2);
  for (int k = 0; k < 100; ++k) {
    const double sign = k % 2 ? 1.0 : -1.0, angle = sign * turn(rng);
    // Read 3 % too far; every step stays within the outlier gate of the model so far.
    bias.Observe({0.0, 0.0, 1.03 * angle}, {0.0, 0.0, angle}, false, true);
  }
  EXPECT_NEAR(bias.turn_error(), -0.03 / 1.03, 0.003);
  EXPECT_DOUBLE_EQ(bias.scale(), 1.0);
  EXPECT_NEAR(bias.drift(), 0.0, 1e-9);
}

TEST(OdometryBiasLearning, RefusesOptionsItCannotLearnWith) {
  auto refused = [](const std::function<void(OdometryBiasOptions&)>& change) {
    OdometryBiasOptions o = RobotOdometryBias();
    change(o);
    try {
      OdometryBias bias(o);
    } catch (const Error& e) {
      return e.code() == ErrorCode::kInvalidArgument;
    }
    return false;
  };
  EXPECT_TRUE(refused([](OdometryBiasOptions& o) { o.prior_travel = 0.0; }));
  EXPECT_TRUE(refused([](OdometryBiasOptions& o) { o.prior_turn = -1.0; }));
  EXPECT_TRUE(refused([](OdometryBiasOptions& o) { o.memory = 0.0; }));
  EXPECT_TRUE(refused([](OdometryBiasOptions& o) { o.min_step = std::nan(""); }));
  EXPECT_TRUE(refused([](OdometryBiasOptions& o) { o.max_scale_error = 1.0; }));
  EXPECT_TRUE(refused([](OdometryBiasOptions& o) { o.outlier_xy = 0.0; }));
  EXPECT_FALSE(refused([](OdometryBiasOptions&) {}));
}

TEST(OdometryBiasLearning, StepsTheWallsDidNotFixTeachNothingOfThatPart) {
  OdometryBias bias(RobotOdometryBias());
  BiasedRobot robot;
  // Along a bare corridor the matched translation is the prediction's own; the heading is fixed.
  robot.Drive(bias, 200, false, true);
  EXPECT_DOUBLE_EQ(bias.scale(), 1.0);
  EXPECT_NEAR(bias.drift(), -0.02 / 1.04, 0.005);
  OdometryBias heading_free(RobotOdometryBias());
  robot.Drive(heading_free, 200, true, false);
  EXPECT_NEAR(heading_free.scale(), 1.0 / 1.03, 0.005);
  EXPECT_DOUBLE_EQ(heading_free.drift(), 0.0);
  EXPECT_DOUBLE_EQ(heading_free.turn_error(), 0.0);
}

TEST(OdometryBiasLearning, WrongMatchesAndShortStepsAreLeftOut) {
  OdometryBias bias(RobotOdometryBias());
  BiasedRobot robot;
  robot.scale = 1.0;
  robot.drift = robot.turn_error = 0.0;
  for (int k = 0; k < 100; ++k) {
    const auto [odometry, matched] = robot.Step();
    bias.Observe(odometry, matched, true, true);
    // A match a corridor's door away, or turned onto the wrong wall.
    bias.Observe(odometry, {matched.x + 0.5, matched.y, matched.theta}, true, false);
    bias.Observe(odometry, {matched.x, matched.y, matched.theta + 0.3}, false, true);
    // A step too short to say anything of the scale, read 50 % long.
    bias.Observe({0.06, 0.0, 0.0}, {0.04, 0.0, 0.0}, true, true);
  }
  EXPECT_NEAR(bias.scale(), 1.0, 0.003);
  EXPECT_NEAR(bias.drift(), 0.0, 0.003);
  EXPECT_NEAR(bias.turn_error(), 0.0, 0.005);
}

TEST(OdometryBiasLearning, FollowsAnErrorThatChangesAndStaysWithinItsBounds) {
  OdometryBias bias(RobotOdometryBias());
  BiasedRobot robot;
  robot.Drive(bias, 300);
  robot.scale = 0.98;  // a heavier load: the wheels' radius shrinks
  robot.Drive(bias, 1500);
  EXPECT_NEAR(bias.scale(), 1.0 / 0.98, 0.005);

  OdometryBiasOptions loose = RobotOdometryBias();
  loose.outlier_xy = loose.outlier_theta = 10.0;
  OdometryBias bounded(loose);
  for (int k = 0; k < 300; ++k) bounded.Observe({1.0, 0.0, 0.0}, {2.0, 0.0, 0.5}, true, true);
  EXPECT_DOUBLE_EQ(bounded.scale(), 1.0 + loose.max_scale_error);
  EXPECT_DOUBLE_EQ(bounded.drift(), loose.max_drift);
}

}  // namespace
}  // namespace navd
