// Exploration goals on a map being built, and a mapping session's changed regions.
#include <gtest/gtest.h>

#include <cmath>

#include "services/common/error.h"
#include "services/mapping/mapping_session.h"
#include "services/navigation/exploration_goal_record.h"
#include "services/navigation/frontier_exploration.h"

namespace navd {
namespace {

// A 10 x 4 m corridor, 5 cm cells: walls all round, the left 4 m seen (free), the rest unknown;
// a second, smaller unknown pocket just beside the robot.
OccupancyGrid HalfSeenCorridor() {
  OccupancyGrid g(200, 80, 0.05, Point2::Zero(), OccupancyGrid::kUnknown);
  g.FillBox({0.0, 0.0}, {4.0, 4.0}, OccupancyGrid::kFree);
  g.FillBox({0.0, 0.0}, {10.0, 0.1});
  g.FillBox({0.0, 3.9}, {10.0, 4.0});
  g.FillBox({0.0, 0.0}, {0.1, 4.0});
  g.FillBox({1.0, 3.0}, {1.05, 3.05}, OccupancyGrid::kUnknown);  // one cell nobody saw
  return g;
}

TEST(Exploration, EachMethodPicksAReachableFrontierAndAPathThroughFreeSpace) {
  const OccupancyGrid map = HalfSeenCorridor();
  const Pose2 robot{1.0, 2.0, 0.0};
  for (const auto method : {navigation::ExplorationMethod::kGreedy, navigation::ExplorationMethod::kFrontier,
                            navigation::ExplorationMethod::kVoronoiFastMarching}) {
    const auto step = navigation::NextExplorationStep(map, robot, method, {robot.translation()});
    ASSERT_TRUE(step);
    EXPECT_EQ(step->path.front(), robot.translation());
    EXPECT_LT(Distance(step->path.back(), step->goal), 1e-9);
    // The goal borders unknown space and keeps its clearance from the walls.
    EXPECT_GE(step->goal.y(), 0.1 + 0.3);
    EXPECT_LE(step->goal.y(), 3.9 - 0.3);
    if (method == navigation::ExplorationMethod::kGreedy) {
      // The nearest unexplored cells: the small pocket beside the robot.
      EXPECT_LT(Distance(step->goal, {1.02, 3.02}), 0.6) << step->goal.transpose();
    } else {
      // Frontier ignores the one-cell pocket (too small); VFM goes for the open unknown, far from
      // where the robot has been: both head for the corridor's unseen end at x = 4 m.
      EXPECT_NEAR(step->goal.x(), 4.0, 0.2) << step->goal.transpose();
    }
  }
}

TEST(Exploration, AFullySeenMapIsComplete) {
  OccupancyGrid g(100, 60, 0.05, Point2::Zero(), OccupancyGrid::kFree);
  g.FillBox({0.0, 0.0}, {5.0, 0.1});
  g.FillBox({0.0, 2.9}, {5.0, 3.0});
  g.FillBox({0.0, 0.0}, {0.1, 3.0});
  g.FillBox({4.9, 0.0}, {5.0, 3.0});
  EXPECT_FALSE(navigation::NextExplorationStep(g, {2.5, 1.5, 0.0}, navigation::ExplorationMethod::kFrontier, {}));
  // Unknown space behind a wall the robot cannot pass is no frontier either.
  g.FillBox({3.0, 0.0}, {3.1, 3.0});
  g.FillBox({3.5, 1.0}, {4.0, 2.0}, OccupancyGrid::kUnknown);
  EXPECT_FALSE(navigation::NextExplorationStep(g, {1.5, 1.5, 0.0}, navigation::ExplorationMethod::kGreedy, {}));
  EXPECT_THROW(navigation::ParseExplorationMethod("random"), Error);
}

TEST(Exploration, AWayTheRobotCameByIsSqueezedThroughWhenItNarrowsBelowTheClearance) {
  // Two rooms, 6 x 3 m, the wall between them at x = 3.0-3.1 m with an 11-cell gap (y 1.2-1.75
  // m): its middle is 0.30 m from both sides. The left room and the right one up to x = 4.5 m
  // seen, the rest unknown. The robot came into the left room through the gap.
  OccupancyGrid g(120, 60, 0.05, Point2::Zero(), OccupancyGrid::kUnknown);
  g.FillBox({0.0, 0.0}, {4.5, 3.0}, OccupancyGrid::kFree);
  g.FillBox({0.0, 0.0}, {6.0, 0.1});
  g.FillBox({0.0, 2.9}, {6.0, 3.0});
  g.FillBox({0.0, 0.0}, {0.1, 3.0});
  for (int y = 0; y < 60; ++y)
    if (y < 24 || y > 34)
      for (int x = 60; x < 62; ++x) g.set({x, y}, OccupancyGrid::kOccupied);
  const Pose2 robot{1.5, 1.5, 0.0};
  navigation::ExplorationOptions o;
  o.clearance = 0.32;
  o.squeeze_clearance = 0.27;
  EXPECT_FALSE(navigation::NextExplorationStep(g, robot, navigation::ExplorationMethod::kFrontier, {}, o));
  // A trail that never came near the gap opens nothing.
  o.squeeze_trail = {{1.0, 0.6}, {1.5, 1.5}};
  EXPECT_FALSE(navigation::NextExplorationStep(g, robot, navigation::ExplorationMethod::kFrontier, {}, o));
  // The robot's own way in is passed, and the goal beyond keeps the full clearance.
  o.squeeze_trail = {{4.0, 1.0}, {3.6, 1.45}, {2.5, 1.5}, {1.5, 1.5}};
  const auto step = navigation::NextExplorationStep(g, robot, navigation::ExplorationMethod::kFrontier, {}, o);
  ASSERT_TRUE(step);
  EXPECT_NEAR(step->goal.x(), 4.5, 0.1) << step->goal.transpose();
  EXPECT_GE(step->goal.y(), 0.1 + 0.32);
  EXPECT_LE(step->goal.y(), 2.9 - 0.32);
  bool through_the_gap = false;
  for (size_t i = 1; i < step->path.size(); ++i) {
    const Point2& a = step->path[i - 1];
    const Point2& b = step->path[i];
    if (a.x() < 3.05 && b.x() >= 3.05) {
      const double y = a.y() + (b.y() - a.y()) * (3.05 - a.x()) / (b.x() - a.x());
      through_the_gap = y > 1.2 && y < 1.75;
    }
  }
  EXPECT_TRUE(through_the_gap);
  // With the right room unseen, the only frontier is in the gap itself, narrower than a goal may
  // stand: none.
  g.FillBox({3.1, 0.1}, {4.5, 2.9}, OccupancyGrid::kUnknown);
  EXPECT_FALSE(navigation::NextExplorationStep(g, robot, navigation::ExplorationMethod::kFrontier, {}, o));
}

TEST(MappingSession, SynchronousRunsReportChangedRegionsAndRefuseAbsurdSizes) {
  mapping::MappingSessionOptions o;
  o.mode = mapping::MappingMode::kKnownPoses;
  o.synchronous = true;
  o.size = 10.0;
  mapping::MappingSession session(o, {5.0, 5.0, 0.0});
  EXPECT_FALSE(session.ChangedSince(0));
  mapping::RangeScan scan;
  scan.angle_min = -0.1;
  scan.angle_increment = 0.1;
  scan.ranges = {2.0f, 2.0f, 2.0f};
  session.Submit({}, {5.0, 5.0, 0.0}, scan);
  const auto region = session.ChangedSince(0);
  ASSERT_TRUE(region);
  const auto map = session.Map();
  EXPECT_TRUE(map->IsOccupied(map->CellOf({7.01, 5.0})));
  EXPECT_LE(region->min.x, map->CellOf({5.0, 5.0}).x);
  EXPECT_GE(region->max.x, map->CellOf({7.0, 5.0}).x);
  EXPECT_FALSE(session.ChangedSince(session.status().version));
  // A scan taken far outside the mapped square changes nothing (and breaks nothing).
  const uint64_t before = session.status().version;
  session.Submit({}, {50.0, 50.0, 0.0}, scan);
  EXPECT_EQ(session.status().version, before);
  EXPECT_FALSE(session.ChangedSince(before));
  session.Finish();
  session.Submit({}, {5.0, 5.0, 0.0}, scan);  // after Finish: ignored
  EXPECT_EQ(session.status().scans, 2u);
  o.size = 1e6;
  EXPECT_THROW(mapping::MappingSession(o, {}), Error);
  // SLAM refuses non-finite odometry: the scan is dropped, the run goes on.
  o.size = 10.0;
  o.mode = mapping::MappingMode::kSlam;
  mapping::MappingSession slam(o, {5.0, 5.0, 0.0});
  slam.Submit({0.0, 0.0, 0.0}, {}, scan);
  slam.Submit({NAN, 0.0, 0.0}, {}, scan);
  EXPECT_EQ(slam.status().dropped, 1u);
  EXPECT_TRUE(slam.status().active);
}

// The worker takes the scans in order, falls behind by at most max_waiting (dropping the oldest
// waiting beyond), and takes every scan still waiting before Finish returns.
TEST(MappingSession, TheWorkerQueuesScansAndFinishTakesTheLastOnes) {
  mapping::MappingSessionOptions o;
  o.mode = mapping::MappingMode::kKnownPoses;
  o.size = 10.0;
  o.max_waiting = 3;
  mapping::MappingSession session(o, {5.0, 5.0, 0.0});
  mapping::RangeScan scan;
  scan.angle_min = -0.1;
  scan.angle_increment = 0.1;
  scan.ranges = {2.0f, 2.0f, 2.0f};
  for (int k = 0; k < 40; ++k) session.Submit({}, {5.0, 5.0 + 0.01 * k, 0.0}, scan);
  session.Finish();
  const mapping::MappingStatus status = session.status();
  EXPECT_EQ(status.scans + status.dropped, 40u);
  EXPECT_GE(status.scans, 3u);
  EXPECT_NEAR(status.pose.y, 5.39, 1e-9);  // the last scan was taken, and taken last
  o.max_waiting = 0;
  EXPECT_THROW(mapping::MappingSession(o, {}), Error);
}

TEST(ExplorationGoalRecord, AGoalGivenUpIsTriedOnceMoreWhenNothingElseIsLeft) {
  navigation::ExplorationGoalRecord record(0.5);
  record.Reached({1.0, 0.0});
  record.GivenUp({5.0, 0.0});
  EXPECT_EQ(record.Excluded().size(), 2u);
  // Nothing else left: the goal given up comes back, the one reached does not.
  EXPECT_TRUE(record.RetryGivenUp());
  ASSERT_EQ(record.Excluded().size(), 1u);
  EXPECT_EQ(record.Excluded()[0], Point2(1.0, 0.0));
  // Given up again (a few centimetres off, the same frontier): out for good, no third try.
  record.GivenUp({5.2, 0.1});
  EXPECT_EQ(record.Excluded().size(), 2u);
  EXPECT_FALSE(record.RetryGivenUp());
  EXPECT_EQ(record.Excluded().size(), 2u);
  // A new goal given up elsewhere gets its own second try.
  record.GivenUp({9.0, 0.0});
  EXPECT_TRUE(record.RetryGivenUp());
  EXPECT_EQ(record.Excluded().size(), 2u);
}

}  // namespace
}  // namespace navd
