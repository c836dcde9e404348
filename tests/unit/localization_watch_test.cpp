// The localisation watch on a sparse laser: a robot carried off between two scans that come
// seconds apart, as in a real log that keeps a scan per metre driven.
#include "services/navigation/localization_watch.h"

#include <gtest/gtest.h>

#include <random>

#include "services/common/world.h"
#include "services/localization/localizer_selector.h"
#include "services/localization/particle_filter.h"
#include "tests/support/simulated_drive.h"

namespace navd::navigation {
namespace {

struct CarriedOff {
  int declared = -1;   // the scan at which the pose was declared lost
  int found = -1;      // the scan after which it was found again
  double error = 0.0;  // m from the truth when found
};

// Localised at the warehouse's start, the robot turns on the spot 0.3 rad between scans 3 s apart;
// after scan 3 it is carried to the far corner (the odometry does not see it) and turns on there.
CarriedOff CarryOff(bool search_ahead) {
  const World world = DefaultWorld();
  localization::LocalizerSelector selector;  // the search beside weighs each scan as it comes
  localization::ParticleFilterOptions po;
  po.seed = 7;
  po.nearby_reset.enabled = false;  // the watch's searches alone
  selector.Add(std::make_unique<localization::ParticleFilterLocalizer>(world.map, po));
  const Pose2 home = world.start, far(8.5, 8.4, M_PI);
  selector.AddOdometry({Pose2(), Eigen::Matrix3d::Zero(), 0.0});
  selector.SetPose(home, Eigen::Matrix3d::Identity() * 1e-4);
  LocalizationWatchOptions wo;
  wo.search_ahead = search_ahead;
  LocalizationWatch watch(selector, wo);
  std::mt19937_64 rng(11);
  CarriedOff out;
  for (int k = 1; k <= 30; ++k) {
    const double t = 3.0 * k, turn = 0.3 * k;
    const Pose2 odometry(0.0, 0.0, turn);
    const Pose2 truth = (k <= 3 ? home : far) * odometry;
    selector.AddOdometry({odometry, Eigen::Matrix3d::Zero(), t});
    localization::ScanReading scan = localization::SimulatedScan(world, truth, rng);
    scan.stamp = t;
    selector.AddScan(scan);
    const bool was_lost = watch.lost();
    watch.Watch(selector.Estimate(), odometry, static_cast<uint64_t>(k), t);
    watch.Search(selector.Estimate(), odometry, watch.lost(), t);
    if (!was_lost && watch.lost()) out.declared = k;
    if (out.declared > 0 && !watch.lost()) {
      out.found = k;
      out.error = Distance(selector.Estimate().pose.translation(), truth.translation());
      break;
    }
  }
  std::printf("search ahead %d: declared lost at scan %d, found after scan %d, %.2f m off\n", search_ahead,
              out.declared, out.found, out.error);
  return out;
}

// Declaring the loss takes lost_scans poor scans, and the whole-map search is believed only once
// it has fitted as many: begun at the first poor scan, it is that much further on when the loss is
// declared, and the robot is found that many scans sooner.
TEST(LocalizationWatch, ASearchBegunAtTheFirstPoorScanFindsACarriedRobotSooner) {
  const CarriedOff ahead = CarryOff(true), after = CarryOff(false);
  EXPECT_EQ(ahead.declared, 6);  // three poor scans, 3 s apart
  EXPECT_EQ(after.declared, 6);
  ASSERT_GT(ahead.found, 0);
  ASSERT_GT(after.found, 0);
  EXPECT_LT(ahead.error, 0.2);
  EXPECT_LT(after.error, 0.2);
  EXPECT_GE(after.found - ahead.found, 2) << "found later without the search ahead";
}

}  // namespace
}  // namespace navd::navigation
