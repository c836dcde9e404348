// The executive's command filters and the leg's progress check, each on its own.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "services/navigation/command_filter.h"
#include "services/navigation/leg_progress.h"
#include "services/navigation/scan_guard.h"
#include "services/navigation/speed_zone_filter.h"
#include "services/navigation/tracked_obstacle_guard.h"

namespace navd::navigation {
namespace {

double Forward(const WheelSpeeds& w) { return 0.5 * (w.left + w.right); }

// A context for a robot at the origin facing +x, with `returns` (robot frame) in front of it.
CommandContext Context(CommandSource source, const std::vector<Point2>& returns, double rear_room = 1.0) {
  CommandContext c;
  c.source = source;
  c.pose_valid = true;
  c.returns = [returns] { return returns; };
  c.moving_rims = [] { return std::vector<Point2>(); };
  c.rear_room = [rear_room] { return rear_room; };
  return c;
}

TEST(ScanGuard, SlowsNavigationBeforeAReturnAheadAndLeavesOtherBehavioursAlone) {
  ScanGuardOptions o;
  o.robot_radius = 0.2;
  o.margin = 0.05;
  o.deceleration = 0.7;
  ScanGuard guard(o);
  const std::vector<Point2> wall{{0.45, 0.0}, {0.45, 0.1}, {0.45, -0.1}};  // 0.25 m from the rim
  const WheelSpeeds fast{0.6, 0.6};
  // Room 0.25 - 0.05 = 0.2 m at 0.7 m/s^2: sqrt(2 * 0.7 * 0.2) = 0.529 m/s.
  const WheelSpeeds capped = guard.Filter(fast, Context(CommandSource::kNavigation, wall));
  EXPECT_NEAR(Forward(capped), std::sqrt(2.0 * 0.7 * 0.2), 1e-6);
  EXPECT_NEAR(Forward(guard.Filter(fast, Context(CommandSource::kGridReentry, wall))), Forward(capped), 1e-12);
  // The emergency stop's recoil and the avoidance's manoeuvres are not the guard's business.
  EXPECT_EQ(Forward(guard.Filter(fast, Context(CommandSource::kOther, wall))), 0.6);
  // Backing straight away from it, or nothing ahead: unchanged.
  EXPECT_EQ(Forward(guard.Filter({-0.1, -0.1}, Context(CommandSource::kNavigation, wall))), -0.1);
  EXPECT_EQ(Forward(guard.Filter(fast, Context(CommandSource::kNavigation, {}))), 0.6);
}

TEST(ScanGuard, TurnsWhileBackingWhenSomethingIsAtTheRimAndTheWayBackIsFree) {
  ScanGuard guard(ScanGuardOptions{});
  const std::vector<Point2> at_rim{{0.22, 0.05}};  // 2 cm from the rim, ahead
  const WheelSpeeds turn{-0.1, 0.1};
  const WheelSpeeds free_back = guard.Filter(turn, Context(CommandSource::kNavigation, at_rim, 1.0));
  EXPECT_LT(Forward(free_back), 0.0);
  EXPECT_GT(free_back.right - free_back.left, 0.0);  // still turning left
  // With no room behind, only the straight part (none here): it stands.
  const WheelSpeeds blocked = guard.Filter(turn, Context(CommandSource::kNavigation, at_rim, 0.0));
  EXPECT_EQ(blocked.left, 0.0);
  EXPECT_EQ(blocked.right, 0.0);
}

TEST(TrackedObstacleGuard, CapsNavigationOnlyWhileTheDetectionRunsAndNotAmongPeople) {
  TrackedObstacleGuard guard(TrackedObstacleGuardOptions{0.2, 0.1, 0.7});
  CommandContext c = Context(CommandSource::kNavigation, {});
  c.tracking_obstacles = true;
  c.moving_rims = [] { return std::vector<Point2>{{0.6, 0.0}}; };  // 0.4 m from the rim
  const WheelSpeeds fast{0.8, 0.8};
  EXPECT_NEAR(Forward(guard.Filter(fast, c)), std::sqrt(2.0 * 0.7 * 0.3), 1e-6);
  c.among_people = true;
  EXPECT_EQ(Forward(guard.Filter(fast, c)), 0.8);
  c.among_people = false;
  c.tracking_obstacles = false;
  EXPECT_EQ(Forward(guard.Filter(fast, c)), 0.8);
  c.tracking_obstacles = true;
  c.source = CommandSource::kGridReentry;
  EXPECT_EQ(Forward(guard.Filter(fast, c)), 0.8);
}

TEST(SpeedZoneFilter, CapsEveryBehaviourInsideAZoneAndStandsTheRobotWithoutAPose) {
  SpeedZoneFilter zones(0.2, SpeedZoneOptions{});
  zones.SetZones(SpeedZones({{"bay", {{-5, -5}, {5, -5}, {5, 5}, {-5, 5}}, 0.2}}));
  CommandContext c = Context(CommandSource::kOther, {});
  const WheelSpeeds w = zones.Filter({0.5, 0.5}, c);
  EXPECT_NEAR(std::max(w.left, w.right), 0.2, 1e-9);
  EXPECT_NEAR(zones.last_limit(), 0.2, 1e-9);
  c.pose_valid = false;  // no zone applies, and the navigator's feedback shows no limit
  EXPECT_EQ(zones.Filter({0.5, 0.5}, c).left, 0.5);
  EXPECT_EQ(zones.last_limit(), 0.0);
}

TEST(CommandFilterChain, AppliesItsFiltersInTheOrderTheyWereAdded) {
  // Each filter gets the previous one's command: halving then adding a tenth is not the reverse.
  struct Halve : CommandFilter {
    WheelSpeeds Filter(const WheelSpeeds& w, const CommandContext&) override { return {w.left / 2, w.right / 2}; }
  };
  struct AddTenth : CommandFilter {
    WheelSpeeds Filter(const WheelSpeeds& w, const CommandContext&) override { return {w.left + 0.1, w.right + 0.1}; }
  };
  CommandFilterChain chain;
  chain.Add(std::make_shared<Halve>());
  chain.Add(std::make_shared<AddTenth>());
  EXPECT_NEAR(chain.Apply({1.0, 1.0}, Context(CommandSource::kOther, {})).left, 0.6, 1e-12);
}

TEST(LegProgress, TimeHeldDoesNotCountAndRecoveriesAreBudgetedPerPlace) {
  LegProgressOptions o;
  o.progress_timeout = 10.0;
  o.max_recoveries = 2;
  o.recovery_radius = 1.0;
  LegProgress p(o);
  p.StartMission(20.0, 0.0);
  EXPECT_TRUE(p.Progressed(19.0, false, 5.0));
  EXPECT_TRUE(p.Progressed(19.0, false, 14.0));
  // Held for 30 s (a pause, another behaviour): the clock stood still.
  p.Stop(14.0);
  p.Drive(44.0);
  EXPECT_TRUE(p.Progressed(19.0, false, 44.5));
  EXPECT_FALSE(p.Progressed(19.0, false, 45.5));
  EXPECT_TRUE(p.AllowRecovery({1.0, 1.0}));
  EXPECT_TRUE(p.TakeRecovery());
  EXPECT_FALSE(p.TakeRecovery());
  EXPECT_TRUE(p.AllowRecovery({1.5, 1.0}));
  EXPECT_FALSE(p.AllowRecovery({1.2, 1.0}));  // a third within a metre: the leg has failed
  EXPECT_TRUE(p.AllowRecovery({5.0, 1.0}));   // somewhere else
  p.WaypointReached(50.0);
  EXPECT_TRUE(p.AllowRecovery({1.2, 1.0}));  // a new leg, a new budget
  EXPECT_EQ(p.Contact({0.0, 0.0}), 1);
  EXPECT_EQ(p.Contact({0.1, 0.0}), 2);
  p.ForgetContacts();
  EXPECT_EQ(p.Contact({0.1, 0.0}), 1);
}

}  // namespace
}  // namespace navd::navigation
