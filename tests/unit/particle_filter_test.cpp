// The particle filter against navsim's robot and laser (the simulator library, no network): it
// corrects a wrong initial pose, tracks a drive through the warehouse while odometry drifts, and
// finds the robot with no prior.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include <cmath>

#include "services/common/error.h"

#include "services/common/world.h"
#include "services/localization/localizer_selector.h"
#include "services/localization/odometry_localizer.h"
#include "services/localization/particle_filter.h"
#include "services/common/diff_drive.h"
#include "simulator/simulation.h"
#include "tests/support/simulated_drive.h"

namespace navd::localization {
namespace {

// navsim's robot at `start` and a particle filter on its map, both seeded, odometry anchored.
struct Scenario {
  Scenario(const Pose2& start, uint64_t seed) : world(WithStart(start)), sim(world, Options(seed)) {
    ParticleFilterOptions po;
    po.seed = seed + 1;
    pf = std::make_unique<ParticleFilterLocalizer>(world.map, po);
    pf->AddOdometry({sim.robot().base().odom_pose(), Eigen::Matrix3d::Zero(), 0.0});
  }
  static World WithStart(const Pose2& start) {
    World w = DefaultWorld();
    w.start = start;
    return w;
  }
  static sim::SimulationOptions Options(uint64_t seed) {
    sim::SimulationOptions o;
    o.seed = seed;
    return o;
  }
  World world;
  sim::Simulation sim;
  std::unique_ptr<ParticleFilterLocalizer> pf;
};

// Seed 000's validation case (section 4.3, with its moving obstacle in view), ten runs: the issue
// asks for 0.02 m and 0.01 rad after the correction.
TEST(ParticleFilter, CorrectsTheSeedZeroValidationCase) {
  for (int run = 0; run < 10; ++run) {
    const sim::Scenario scenario = SeedZeroValidationScenario();
    sim::Simulation s(scenario, Scenario::Options(100 + 2 * run));
    ParticleFilterOptions po;
    po.seed = 101 + 2 * run;
    ParticleFilterLocalizer pf(scenario.world.map, po);
    const Errors e = RunSeedZeroValidation(s, pf);
    std::printf("validation run %d: worst error standing still %.4f m, %.4f rad\n", run, e.position, e.heading);
    EXPECT_LT(e.position, 0.02) << "run " << run;
    EXPECT_LT(e.heading, 0.01) << "run " << run;
  }
}

// The beam model (AMCL's "beam": ray casts from each particle) on the same case, and on a drive with
// biased odometry.
TEST(ParticleFilter, BeamModelCorrectsTheValidationCaseAndTracksADrive) {
  ParticleFilterOptions po;
  po.sensor_model = SensorModel::kBeam;
  for (int run = 0; run < 3; ++run) {
    const sim::Scenario scenario = SeedZeroValidationScenario();
    sim::Simulation s(scenario, Scenario::Options(400 + run));
    po.seed = 401 + run;
    ParticleFilterLocalizer pf(scenario.world.map, po);
    const Errors e = RunSeedZeroValidation(s, pf);
    std::printf("beam model validation run %d: %.4f m, %.4f rad\n", run, e.position, e.heading);
    EXPECT_LT(e.position, 0.03) << "run " << run;
    EXPECT_LT(e.heading, 0.02) << "run " << run;
  }
  World world = DefaultWorld();
  sim::Simulation s(world, {});
  ParticleFilterLocalizer pf(world.map, po);
  pf.AddOdometry({s.robot().base().odom_pose(), Eigen::Matrix3d::Zero(), 0.0});
  pf.SetPose(world.start, Eigen::Matrix3d::Zero());
  const Errors e = Drive(s, pf, 50.0, UpTheCorridorAndBack, 50.0, {0.03, 0.04});
  std::printf("beam model drive: worst %.3f m / %.3f rad, mean %.4f m\n", e.position, e.heading, e.mean_position);
  EXPECT_LT(e.position, 0.15);
  EXPECT_LT(e.mean_position, 0.05);
}

TEST(ParticleFilter, TracksADriveWhileOdometryDrifts) {
  World world = DefaultWorld();
  world.robot.encoder_noise = 0.03;  // six times navsim's default slip
  sim::Simulation s(world, {});
  ParticleFilterLocalizer pf(world.map);
  pf.AddOdometry({s.robot().base().odom_pose(), Eigen::Matrix3d::Zero(), 0.0});
  pf.SetPose(world.start, Eigen::Matrix3d::Zero());
  // Up the corridor and back: 2 x ~6 m.
  const Errors e = Drive(s, pf, 50.0, UpTheCorridorAndBack, 50.0);
  const Pose2 odom = world.start * s.robot().base().odom_pose();
  const Pose2 truth = s.robot().base().true_pose();
  std::printf("drive: filter worst error %.3f m / %.3f rad; odometry error at the end %.3f m\n", e.position, e.heading,
              std::hypot(odom.x - truth.x, odom.y - truth.y));
  EXPECT_LT(e.position, 0.10);
  EXPECT_LT(e.heading, 0.05);
}

// Wake-up (seed 000 section 7): with no prior at all, the filter finds the robot in the rooms once
// it has looked around. (The long featureless corridor is ambiguous along its length: there the
// filter can settle on the wrong stretch; see the issue note.)
TEST(ParticleFilter, RelocalisesGloballyWithoutAPrior) {
  int found = 0;
  const Pose2 starts[3] = {{8.5, 8.4, M_PI}, {4.0, 5.0, 0.0}, {3.0, 2.6, M_PI / 2}};
  for (int run = 0; run < 3; ++run) {
    Scenario sc(starts[run], 300 + 2 * run);
    sim::Simulation& s = sc.sim;
    ParticleFilterLocalizer& pf = *sc.pf;
    pf.GlobalRelocalize();
    const Errors e = Drive(
        s, pf, 14.0,
        [](double t) {
          return Twist2{0.0, t < 12 ? 0.6 : 0.0};
        },
        1.0);
    std::printf("global relocalisation run %d: error %.3f m, %.3f rad, %zu particles\n", run, e.position, e.heading,
                pf.particle_count());
    // Found = settled on the true place (a wrong mode is metres away); the residual error while
    // turning on the spot is a few centimetres to a decimetre.
    if (e.position < 0.15 && e.heading < 0.05) ++found;
  }
  EXPECT_EQ(found, 3);
}

// The odometry a localiser is fed, moved by `offset` (odom frame) from when it is set: a robot
// whose odometry jumps while it stands, as if carried off and set down where it was.
class OffsetOdometry : public Localizer {
 public:
  explicit OffsetOdometry(Localizer& inner) : inner_(inner) {}
  std::string name() const override { return inner_.name(); }
  void AddOdometry(const OdometryReading& reading) override {
    OdometryReading r = reading;
    r.pose = offset * reading.pose;
    inner_.AddOdometry(r);
  }
  bool AddScan(const ScanReading& scan) override { return inner_.AddScan(scan); }
  PoseEstimate Estimate() const override { return inner_.Estimate(); }
  MethodContext Suitability(bool laser_fresh) const override { return inner_.Suitability(laser_fresh); }
  Pose2 offset;

 private:
  void ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) override { inner_.SetPose(pose, covariance); }
  Localizer& inner_;
};

// A pose lost suddenly a few metres away: the filter tracks the robot turning in place, then its
// odometry jumps 2.5 m while the robot stands. The nearby reset finds where the scans fit and the
// filter is back on the truth within a few scans, counting one relocation; without it, the
// filter stays away. A pose told wrong by SetPose is not searched for (the wake-up's business).
TEST(ParticleFilter, FindsAPoseLostSuddenlyAFewMetresAway) {
  const Pose2 truth{4.0, 5.0, 0.0};
  auto turn = [](double) { return Twist2{0.0, 0.4}; };
  for (const bool reset : {true, false}) {
    Scenario sc(truth, 500);
    ParticleFilterOptions po;
    po.nearby_reset.enabled = reset;
    sc.pf = std::make_unique<ParticleFilterLocalizer>(sc.world.map, po);
    OffsetOdometry fed(*sc.pf);
    fed.AddOdometry({sc.sim.robot().base().odom_pose(), Eigen::Matrix3d::Zero(), 0.0});
    fed.SetPose(truth, Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal());
    const Errors tracked = Drive(sc.sim, fed, 2.0, turn, 1.0);
    EXPECT_LT(tracked.position, 0.05);
    fed.offset =
        sc.sim.robot().base().odom_pose() * Pose2(0.0, -2.5, 0.0) * sc.sim.robot().base().odom_pose().inverse();
    const Errors e = Drive(sc.sim, fed, 4.0, turn, 1.0);
    const uint64_t relocations = sc.pf->Estimate().relocations;
    std::printf("odometry jumped 2.5 m, nearby reset %s: error after 3 s %.3f m, %.3f rad; %llu relocations\n",
                reset ? "on" : "off", e.position, e.heading, static_cast<unsigned long long>(relocations));
    if (reset) {
      EXPECT_LT(e.position, 0.1);
      EXPECT_LT(e.heading, 0.05);
      EXPECT_EQ(relocations, 1u);
    } else {
      EXPECT_GT(e.position, 1.0);
      EXPECT_EQ(relocations, 0u);
    }
  }
  // Told a pose 2.5 m off: no reset; the filter stays where it was told.
  Scenario sc(truth, 502);
  sc.pf->SetPose({4.0, 2.5, 0.0}, Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal());
  const Errors told = Drive(sc.sim, *sc.pf, 3.0, turn, 1.0);
  std::printf("told 2.5 m off: error after 2 s %.3f m, %llu relocations\n", told.position,
              static_cast<unsigned long long>(sc.pf->Estimate().relocations));
  EXPECT_EQ(sc.pf->Estimate().relocations, 0u);
}

TEST(ParticleFilter, IgnoresMalformedInput) {
  World world = DefaultWorld();
  ParticleFilterLocalizer pf(world.map);
  pf.AddOdometry({{0, 0, 0}, Eigen::Matrix3d::Zero(), 0.0});
  pf.SetPose(world.start, Eigen::Matrix3d::Zero());
  pf.AddOdometry({{NAN, 0, 0}, Eigen::Matrix3d::Zero(), 0.1});
  ScanReading bad;
  EXPECT_FALSE(pf.AddScan(bad));  // no ranges
  bad.ranges.assign(683, NAN);
  bad.angle_increment = 0.006;
  bad.range_max = 4.0;
  EXPECT_FALSE(pf.AddScan(bad));  // no usable beams
  const auto e = pf.Estimate();
  EXPECT_TRUE(e.pose.finite());
  EXPECT_NEAR(e.pose.x, world.start.x, 0.5);
}

// An omnidirectional base slides sideways: the omni motion model carries the particles across
// with their headings, where the diff-drive model reads the slide as two quarter turns and
// smears the headings.
TEST(ParticleFilter, OmniModelSlidesSidewaysWithoutSmearingHeadings) {
  const World world = DefaultWorld();
  auto heading_spread_after_slide = [&](MotionModel model, Pose2* mean) {
    ParticleFilterOptions o;
    o.motion_model = model;
    o.seed = 3;
    // Without scans the cloud follows the odometry in steps of 20 update thresholds: 0.2 m here.
    o.update_min_distance = o.update_min_angle = 0.01;
    ParticleFilterLocalizer pf(world.map, o);
    pf.AddOdometry({Pose2(0, 0, 0), Eigen::Matrix3d::Zero(), 0.0});
    pf.SetPose(world.start, Eigen::Matrix3d::Zero());
    for (int i = 1; i <= 80; ++i) pf.AddOdometry({Pose2(0, 0.01 * i, 0), Eigen::Matrix3d::Zero(), 0.02 * i});
    *mean = pf.Estimate().pose;
    return std::sqrt(pf.Estimate().covariance(2, 2));
  };
  Pose2 omni_mean, diff_mean;
  const double omni = heading_spread_after_slide(MotionModel::kOmni, &omni_mean);
  const double diff = heading_spread_after_slide(MotionModel::kDiffDrive, &diff_mean);
  std::printf("0.8 m sideways: heading spread omni %.3f rad, diff-drive %.3f rad\n", omni, diff);
  // Started at 0.1 rad; the omni model adds sqrt(alpha2) x 0.2 m per step, the diff model ~0.7 rad.
  EXPECT_LT(omni, 0.2);
  EXPECT_GT(diff, 0.5);
  // The slide itself: 0.8 m to the robot's left in the map frame.
  const Point2 left =
      world.start.translation() + 0.8 * Point2(-std::sin(world.start.theta), std::cos(world.start.theta));
  EXPECT_LT((omni_mean.translation() - left).norm(), 0.05);
  EXPECT_NEAR(NormalizeAngle(omni_mean.theta - world.start.theta), 0.0, 0.05);
}

// The scenario's particle filter, told the robot is at `told`, as the selector's one method. The
// estimate is to keep that wrong pose: without the filter's own nearby reset, which finds a robot
// this near by itself (FindsARobotCarriedAFewMetresWithinAFewScans).
void AddAFilterTold(Scenario& sc, LocalizerSelector& selector, const Pose2& told) {
  ParticleFilterOptions po;
  po.seed = 301;
  po.nearby_reset.enabled = false;
  sc.pf = std::make_unique<ParticleFilterLocalizer>(sc.world.map, po);
  sc.pf->AddOdometry({sc.sim.robot().base().odom_pose(), Eigen::Matrix3d::Zero(), 0.0});
  selector.Add(std::move(sc.pf));
  selector.SetPose(told, Eigen::Matrix3d::Identity() * 1e-3);
}

// 12 s turning on the spot at 0.6 rad/s, then 2 s standing (the last second judged).
void TurnOnTheSpot(sim::Simulation& sim, Localizer& localizer) {
  Drive(
      sim, localizer, 14.0,
      [](double t) {
        return Twist2{0.0, t < 12 ? 0.6 : 0.0};
      },
      1.0);
}

// The wake-up's whole-map search beside the estimate (Localizer::StartSearch): the estimate goes on
// tracking what it had (here a pose 5.5 m off) while a second filter searches the whole map; the
// search finds the robot (as RelocalisesGloballyWithoutAPrior does) and ending it either keeps the
// estimate or moves it there.
TEST(LocalizerSelector, AWholeMapSearchRunsBesideTheEstimate) {
  const Pose2 truth(8.5, 8.4, M_PI), told(4.0, 5.0, 0.0);
  for (const bool adopt : {false, true}) {
    Scenario sc(truth, 300);
    LocalizerSelector selector;
    AddAFilterTold(sc, selector, told);
    EXPECT_FALSE(selector.SearchEstimate().valid);
    ASSERT_TRUE(selector.StartSearch());
    TurnOnTheSpot(sc.sim, selector);
    const Pose2 at = sc.sim.robot().base().true_pose();
    const PoseEstimate found = selector.SearchEstimate();
    ASSERT_TRUE(found.valid);
    EXPECT_LT(Distance(found.pose.translation(), at.translation()), 0.15) << "the search finds the robot";
    EXPECT_GT(Distance(selector.Estimate().pose.translation(), at.translation()), 3.0) << "the estimate kept its own";
    selector.EndSearch(adopt);
    EXPECT_FALSE(selector.SearchEstimate().valid);
    const double error = Distance(selector.Estimate().pose.translation(), at.translation());
    if (adopt) {
      EXPECT_LT(error, 0.15) << "adopted, the estimate is the search's";
    } else {
      EXPECT_GT(error, 3.0) << "ended without adopting, the estimate is as it was";
    }
  }
}

// Hands each scan to a selector whose search runs on a thread of its own, and on every other scan
// waits (up to 0.3 s: a filter skips scans while the robot stands still) until the search has weighed it, so that the
// search keeps up with the drive as it would in real time and still drops scans that come while it is busy.
class PacedForTheSearch : public Localizer {
 public:
  explicit PacedForTheSearch(LocalizerSelector& s) : s_(s) {}
  std::string name() const override { return s_.name(); }
  void AddOdometry(const OdometryReading& r) override { s_.AddOdometry(r); }
  bool AddScan(const ScanReading& scan) override {
    const bool used = s_.AddScan(scan);
    if (++scans_ % 2 == 0) {
      for (int i = 0; i < 30 && s_.SearchEstimate().stamp < scan.stamp; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return used;
  }
  PoseEstimate Estimate() const override { return s_.Estimate(); }
  MethodContext Suitability(bool laser_fresh) const override { return s_.Suitability(laser_fresh); }

 private:
  void ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) override { s_.SetPose(pose, covariance); }
  LocalizerSelector& s_;
  int scans_ = 0;
};

// navd's search runs on a thread of its own (BesideSearch): it is handed the scans and the
// odometry, weighs the newest scan when it is free and carries its particles through all the
// odometry up to it; it finds the robot as the synchronous one does, and is adopted the same way.
TEST(LocalizerSelector, ASearchOnItsOwnThreadFindsTheRobotToo) {
  const Pose2 truth(8.5, 8.4, M_PI), told(4.0, 5.0, 0.0);
  Scenario sc(truth, 300);
  LocalizerSelector selector(/*search_on_its_own_thread=*/true);
  AddAFilterTold(sc, selector, told);
  ASSERT_TRUE(selector.StartSearch());
  PacedForTheSearch paced(selector);
  TurnOnTheSpot(sc.sim, paced);
  const Pose2 at = sc.sim.robot().base().true_pose();
  const PoseEstimate found = selector.SearchEstimate();
  ASSERT_TRUE(found.valid);
  EXPECT_LT(Distance(found.pose.translation(), at.translation()), 0.15) << "the search finds the robot";
  EXPECT_GT(Distance(selector.Estimate().pose.translation(), at.translation()), 3.0) << "the estimate kept its own";
  selector.EndSearch(true);
  EXPECT_LT(Distance(selector.Estimate().pose.translation(), at.translation()), 0.15) << "adopted";
}

// With odometry answering (as "auto" picks it while the scans fit poorly) the search is still a
// particle filter's; a pose set by hand ends it.
TEST(LocalizerSelector, ASearchRunsWhicheverMethodAnswersAndAPoseSetEndsIt) {
  World world = DefaultWorld();
  LocalizerSelector selector;
  selector.Add(std::make_unique<OdometryLocalizer>(world.start));
  selector.Add(std::make_unique<ParticleFilterLocalizer>(world.map));
  selector.AddOdometry({Pose2(), Eigen::Matrix3d::Zero(), 0.0});
  selector.Select("odometry");
  ASSERT_TRUE(selector.StartSearch());
  EXPECT_TRUE(selector.SearchEstimate().valid);
  EXPECT_GT(selector.SearchEstimate().PositionSpread(), 1.0) << "scattered over the map";
  selector.SetPose(world.start, Eigen::Matrix3d::Identity() * 1e-3);
  EXPECT_FALSE(selector.SearchEstimate().valid);
  selector.EndSearch(true);  // nothing to adopt
  EXPECT_LT(Distance(selector.Estimate().pose.translation(), world.start.translation()), 1e-9);
}

// "auto" (book chapter 10): the arbiter hands the pose to the particle filter while its scans fit
// the map, to odometry ten evaluations (2 s) after the laser has been silent for a second, and back
// when scans return.
TEST(LocalizerSelector, AutoFollowsTheLaserWithTheChapterTenArbiter) {
  World world = DefaultWorld();
  sim::Simulation s(world, {});
  LocalizerSelector selector;
  selector.Add(std::make_unique<OdometryLocalizer>(world.start));
  auto pf = std::make_unique<ParticleFilterLocalizer>(world.map);
  const std::string amcl = pf->name();
  const ParticleFilterLocalizer& filter = *pf;
  selector.Add(std::move(pf));
  selector.AddOdometry({s.robot().base().odom_pose(), Eigen::Matrix3d::Zero(), 0.0});
  selector.SetPose(world.start, Eigen::Matrix3d::Zero());
  EXPECT_EQ(selector.Methods(), (std::vector<std::string>{"odometry", amcl, "auto"}));
  selector.Select("auto");
  EXPECT_TRUE(selector.automatic());
  // Returns the method in charge after `seconds` of slow circles, with or without the laser.
  auto run = [&](double seconds, bool laser) {
    const double end = s.now() + seconds;
    while (s.now() < end) {
      s.Command(0, {0.2, 0.0, 0.2});
      const auto out = s.Step();
      if (out.robots[0].odom)
        selector.AddOdometry({s.robot().base().odom_pose(), s.robot().base().odom_covariance(), s.now()});
      if (laser && out.robots[0].scan) selector.AddScan(ToScan(s, *out.robots[0].scan));
    }
    return selector.name();
  };
  EXPECT_EQ(run(1.5, true), "odometry");  // no laser yet at the first evaluation; 10 wins needed
  EXPECT_EQ(run(2.0, true), amcl);
  EXPECT_GT(filter.Suitability(true).criteria[2], 3.0) << filter.Estimate().quality;  // a good fit
  EXPECT_EQ(run(2.5, false), amcl);  // silent for 1 s, then 1.5 s of odometry wins
  EXPECT_EQ(run(1.0, false), "odometry");
  EXPECT_EQ(run(3.0, true), amcl) << "filter quality " << filter.Estimate().quality;
  try {
    selector.Select("ekf");
    ADD_FAILURE() << "an unknown method was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("(known: odometry, " + amcl + ", auto)"), std::string::npos) << e.what();
  }
  selector.Select("odometry");
  EXPECT_FALSE(selector.automatic());
  EXPECT_EQ(run(3.0, true), "odometry");
}

}  // namespace
}  // namespace navd::localization
