// The whole-map scan search on navsim's warehouse: from scans ray-cast at random free poses (a
// 360-degree laser of 8 m, as navsim's), the true pose is among the candidates every time and
// first nearly every time (the warehouse has look-alike aisles; the particle filter's next scans
// tell them apart). Also what it does with too few points.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "services/common/ray_caster.h"
#include "services/common/world.h"
#include "services/localization/global_scan_search.h"
#include "services/localization/nearby_reset.h"

namespace navd::localization {
namespace {

// A pose anywhere on `map`, any heading, at least 0.5 m from every wall.
Pose2 RandomClearPose(const OccupancyGrid& map, const RayCaster& caster, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  while (true) {
    const Pose2 p{map.origin().x() + u(rng) * map.width() * map.resolution(),
                  map.origin().y() + u(rng) * map.height() * map.resolution(), NormalizeAngle(u(rng) * 2 * M_PI)};
    if (caster.Clearance(p.translation()) > 0.5) return p;
  }
}

// navsim's warehouse and what the searches need on it: its likelihood field, the scan search, and a
// ray caster for the scans.
struct Warehouse {
  World world = DefaultWorld();
  LikelihoodField field{world.map};
  GlobalScanSearch search{world.map, field};
  RayCaster caster{world.map};
};

// End points (robot frame) of a 360-degree, 8 m laser at `pose`, as navsim's; no-returns dropped.
std::vector<Point2> ScanFrom(const RayCaster& caster, const Pose2& pose) {
  std::vector<Point2> points;
  for (int i = 0; i < 360; ++i) {
    const double a = i * M_PI / 180.0, r = caster.CastOpenEdge(pose.translation(), pose.theta + a, 8.0);
    if (r < 8.0) points.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return points;
}

TEST(GlobalScanSearch, FindsRandomWarehousePosesFromOneScan) {
  const Warehouse warehouse;
  const World& world = warehouse.world;
  const GlobalScanSearch& search = warehouse.search;
  const RayCaster& caster = warehouse.caster;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int first = 0, among = 0, runs = 0;
  while (runs < 30) {
    const Pose2 truth{world.map.origin().x() + u(rng) * world.map.width() * world.map.resolution(),
                      world.map.origin().y() + u(rng) * world.map.height() * world.map.resolution(),
                      NormalizeAngle(u(rng) * 2 * M_PI)};
    const CellIndex cell = world.map.CellOf(truth.translation());
    if (!world.map.Contains(cell) || world.map.at(cell) != OccupancyGrid::kFree) continue;
    if (caster.Cast(truth.translation(), 0.0, 0.3) < 0.3) continue;  // not inside a shelf's rim
    ++runs;
    const std::vector<Point2> points = ScanFrom(caster, truth);
    const std::vector<PoseCandidate> found = search.Search(points);
    auto near = [&](const PoseCandidate& c) {
      return std::hypot(c.pose.x - truth.x, c.pose.y - truth.y) < 0.3 &&
             std::abs(NormalizeAngle(c.pose.theta - truth.theta)) < 0.1;
    };
    if (!found.empty() && near(found.front())) ++first;
    if (std::any_of(found.begin(), found.end(), near)) ++among;
  }
  std::printf("whole-map scan search: true pose first %d of %d, among the candidates %d\n", first, runs, among);
  EXPECT_EQ(among, runs);
  EXPECT_GE(first, runs * 8 / 10);
  EXPECT_TRUE(search.Search({{1.0, 0.0}, {0.0, 1.0}}).empty());
}

// A window keeps the search to poses near a centre: from a scan taken at a pose, a window around
// that pose finds it first; a window elsewhere finds nothing within it (every candidate is
// inside), and Score rates the true pose as the search does.
TEST(GlobalScanSearch, AWindowKeepsTheSearchNearItsCentre) {
  const Warehouse warehouse;
  const GlobalScanSearch& search = warehouse.search;
  const RayCaster& caster = warehouse.caster;
  const Pose2 truth{4.0, 5.0, 0.3};
  const std::vector<Point2> points = ScanFrom(caster, truth);
  const SearchWindow near{{5.5, 6.0, 1.0}, 3.0, 1.0};
  const std::vector<PoseCandidate> found = search.Search(points, &near);
  ASSERT_FALSE(found.empty());
  EXPECT_LT(std::hypot(found.front().pose.x - truth.x, found.front().pose.y - truth.y), 0.1);
  EXPECT_LT(std::abs(NormalizeAngle(found.front().pose.theta - truth.theta)), 0.05);
  EXPECT_NEAR(search.Score(found.front().pose, points), found.front().score, 1e-9);
  EXPECT_GT(search.Score(truth, points), 0.9);
  const SearchWindow away{{truth.x + 6.0, truth.y, 0.0}, 2.0, 0.3};
  for (const PoseCandidate& c : search.Search(points, &away)) {
    EXPECT_LE(std::hypot(c.pose.x - away.centre.x, c.pose.y - away.centre.y), 2.0 + 0.3);
    EXPECT_LE(std::abs(NormalizeAngle(c.pose.theta - away.centre.theta)), 0.3 + 0.1);
    EXPECT_LT(c.score, search.Score(truth, points));
  }
}

// A map made in memory holds graded values (a mapper's probabilities: free space seen by many
// clamped misses at a few percent, not 0). The search looks there as on the same map saved by
// map_server rules, where those cells read 0: the same pose first, at the same score.
TEST(GlobalScanSearch, SearchesAMapOfGradedValuesAsItsSavedForm) {
  const World world = DefaultWorld();
  OccupancyGrid graded = world.map;
  for (int y = 0; y < graded.height(); ++y)
    for (int x = 0; x < graded.width(); ++x)
      if (graded.at({x, y}) == OccupancyGrid::kFree) graded.set({x, y}, static_cast<int8_t>(5 + (x * 7 + y * 3) % 14));
  const LikelihoodField field(world.map), graded_field(graded);
  const GlobalScanSearch search(world.map, field), graded_search(graded, graded_field);
  const RayCaster caster(world.map);
  const Pose2 truth{4.0, 5.0, 0.3};
  const std::vector<Point2> points = ScanFrom(caster, truth);
  const SearchWindow window{{5.0, 5.5, 0.5}, 3.0, 1.0};
  const std::vector<PoseCandidate> saved = search.Search(points, &window);
  const std::vector<PoseCandidate> in_memory = graded_search.Search(points, &window);
  ASSERT_FALSE(saved.empty());
  ASSERT_FALSE(in_memory.empty());
  EXPECT_LT(std::hypot(in_memory.front().pose.x - truth.x, in_memory.front().pose.y - truth.y), 0.1);
  EXPECT_NEAR(in_memory.front().score, saved.front().score, 1e-9);
  EXPECT_FALSE(OccupancyGrid::IsFreeValue(OccupancyGrid::kUnknown));
  EXPECT_FALSE(OccupancyGrid::IsFreeValue(40));
  EXPECT_FALSE(OccupancyGrid::IsFreeValue(OccupancyGrid::kOccupied));
}

// Clutter is not a lost pose. In the warehouse, with a cart (a disc of 0.35 m) 0.6-1 m from the
// robot hiding the racks behind it, a scan fits the true pose poorly, yet from the true pose it
// passes through no wall (SeeThrough 0), and the nearby reset draws no pose away from it, nor
// while a pose 2 m off awaits confirmation. A robot 2 m from the estimate is still found: the
// scan passes through walls from the estimate.
TEST(NearbyReset, LeavesARightEstimateAmongCartsAloneAndFindsAMovedRobot) {
  const Warehouse warehouse;
  const World& world = warehouse.world;
  const GlobalScanSearch& search = warehouse.search;
  const RayCaster& caster = warehouse.caster;
  const NearbyReset reset;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int wrong_draws = 0, moved_found = 0, moved_runs = 0;
  for (int run = 0; run < 60; ++run) {
    const Pose2 truth = RandomClearPose(world.map, caster, rng);
    // The cart, robot frame, and the scan with it.
    const double bearing = (u(rng) - 0.5) * 2.0 * M_PI, distance = 0.6 + 0.4 * u(rng), radius = 0.35;
    const Point2 cart = distance * Point2(std::cos(bearing), std::sin(bearing));
    std::vector<Point2> cluttered;
    for (int i = 0; i < 360; ++i) {
      const double a = i * M_PI / 180.0;
      const Point2 dir(std::cos(a), std::sin(a));
      double r = caster.CastOpenEdge(truth.translation(), truth.theta + a, 8.0);
      const double along = dir.dot(cart), across2 = cart.squaredNorm() - along * along;
      if (along > 0.0 && across2 < radius * radius) r = std::min(r, along - std::sqrt(radius * radius - across2));
      if (r < 8.0) cluttered.emplace_back(r * dir);
    }
    EXPECT_EQ(search.SeeThrough(truth, cluttered, 0.15), 0.0);
    const std::optional<NearbyReset::Found> drawn = reset.Check(search, truth, 0.5, cluttered);
    if (drawn && Distance(drawn->best.pose.translation(), truth.translation()) > 0.5) ++wrong_draws;
    // Nor while a pose 2 m off awaits confirmation: found there, it would be drawn.
    const NearbyReset::Expected elsewhere{truth * Pose2(0.0, 2.0, 0.0), 0.5, 0.2};
    const std::optional<NearbyReset::Found> confirmed = reset.Check(search, truth, 0.5, cluttered, &elsewhere);
    if (confirmed && Distance(confirmed->best.pose.translation(), truth.translation()) > 0.5) ++wrong_draws;
    const Pose2 beside = truth * Pose2(0.0, 2.0, 0.0);
    if (run % 3 != 0 || caster.Clearance(beside.translation()) < 0.4) continue;
    ++moved_runs;
    const std::optional<NearbyReset::Found> found = reset.Check(search, beside, 0.5, ScanFrom(caster, truth));
    if (found && Distance(found->best.pose.translation(), truth.translation()) < 0.3) ++moved_found;
  }
  std::printf(
      "nearby reset: poses drawn away from a right estimate among carts %d of 120, moved robot found %d of %d\n",
      wrong_draws, moved_found, moved_runs);
  EXPECT_EQ(wrong_draws, 0);
  EXPECT_GE(moved_runs, 5);
  EXPECT_GE(moved_found, moved_runs * 9 / 10);
}

// A robot carried off is found by one search and must be found again by the next, where the
// odometry has carried it since (1 m on); the estimate, lost, has meanwhile run 6 m the other
// way, out of reach of a search around it. The search around the expected pose finds it, and that
// confirms the expected pose but not one 1 m off. A found pose carried with a drifted heading
// settles back onto the scan.
TEST(NearbyReset, LooksForAPoseAwaitingConfirmationWhereTheOdometryCarriedIt) {
  const Warehouse warehouse;
  const World& world = warehouse.world;
  const GlobalScanSearch& search = warehouse.search;
  const RayCaster& caster = warehouse.caster;
  const NearbyReset reset;
  std::mt19937_64 rng(5);
  int runs = 0, confirmed = 0, confirmed_off = 0, settled = 0;
  for (; runs < 30; ++runs) {
    const Pose2 truth = RandomClearPose(world.map, caster, rng);
    const std::vector<Point2> points = ScanFrom(caster, truth);
    // The first search found the robot 1 m back, at odometry `found_at` (its own frame, turned
    // from the map's).
    const Pose2 found = truth * Pose2(-1.0, 0.0, 0.0);
    const Pose2 found_at(3.0, -2.0, 1.2), now = found_at * Pose2(1.0, 0.0, 0.0);
    const NearbyReset::Expected expected = reset.Expect(found, found_at, now);
    EXPECT_LT(Distance(expected.pose.translation(), truth.translation()), 1e-9);
    EXPECT_NEAR(expected.tolerance_xy, reset.options().confirm_xy + reset.options().confirm_xy_per_metre, 1e-9);
    const Pose2 run_off = truth * Pose2(0.0, 6.0, 0.0);
    const std::optional<NearbyReset::Found> again = reset.Check(search, run_off, 0.2, points, &expected);
    if (again && reset.Confirms(expected, again->best.pose)) ++confirmed;
    NearbyReset::Expected off = expected;
    off.pose = expected.pose * Pose2(0.0, 1.0, 0.0);
    if (again && reset.Confirms(off, again->best.pose)) ++confirmed_off;
    const Pose2 drifted = truth * Pose2(0.2, -0.15, 0.08);
    if (Distance(reset.Settle(search, drifted, points).translation(), truth.translation()) < 0.1) ++settled;
  }
  std::printf("nearby reset: confirmed %d of %d where the odometry carried the pose, %d 1 m off; settled %d\n",
              confirmed, runs, confirmed_off, settled);
  EXPECT_GE(confirmed, runs * 9 / 10);
  EXPECT_EQ(confirmed_off, 0);
  EXPECT_GE(settled, runs * 9 / 10);
}

// A later scan tells a search's find from a look-alike rival without another search: carried on
// by the odometry (0.6 m and 0.2 rad on), the one the scan fits is confirmed. The look-alike is
// the whole-map search's best pose 1 m or more from the truth (the warehouse's aisles): found
// first with the truth as its rival, the truth is confirmed and the look-alike never. A find the
// scan does not fit (2.5 m off, turned) is not confirmed. The lost estimate is 2 m off.
TEST(NearbyReset, ALaterScanConfirmsTheFindOrItsRivalWhereTheOdometryCarriedThem) {
  const Warehouse warehouse;
  const World& world = warehouse.world;
  const GlobalScanSearch& search = warehouse.search;
  const RayCaster& caster = warehouse.caster;
  const NearbyReset reset;
  std::mt19937_64 rng(17);
  const Pose2 step(0.6, 0.0, 0.2), found_at(3.0, -2.0, 1.2), now = found_at * step;
  int runs = 0, confirmed = 0, look_alikes = 0, rival_confirmed = 0, wrong_confirmed = 0;
  while (runs < 30) {
    const Pose2 truth = RandomClearPose(world.map, caster, rng), later = truth * step;
    if (caster.Clearance(later.translation()) < 0.4) continue;
    ++runs;
    const std::vector<Point2> points = ScanFrom(caster, later);
    const Pose2 estimate = later * Pose2(-1.5, 1.3, 0.0);
    auto confirmed_at = [&](const NearbyReset::Found& found) {
      return reset.ConfirmWhereCarried(search, found, found_at, now, estimate, points);
    };
    // Only `where` confirmed.
    auto just = [](const std::vector<Pose2>& poses, const Pose2& where) {
      return poses.size() == 1 && Distance(poses.front().translation(), where.translation()) < 0.1;
    };
    if (just(confirmed_at({{truth, 0.95}, {}}), later)) ++confirmed;
    for (const PoseCandidate& c : search.Search(ScanFrom(caster, truth))) {
      if (Distance(c.pose.translation(), truth.translation()) < 1.0) continue;
      ++look_alikes;
      const std::vector<Pose2> chosen = confirmed_at({c, {{truth, 0.95}}});
      if (just(chosen, later)) ++rival_confirmed;
      for (const Pose2& pose : chosen)
        if (Distance(pose.translation(), later.translation()) > 0.5) ++wrong_confirmed;
      break;
    }
    if (!confirmed_at({{truth * Pose2(0.0, 2.5, 0.3), 0.95}, {}}).empty()) ++wrong_confirmed;
  }
  std::printf(
      "nearby reset, a later scan: the find confirmed %d of %d, the truth as a look-alike's rival %d of %d, "
      "a wrong pose %d\n",
      confirmed, runs, rival_confirmed, look_alikes, wrong_confirmed);
  EXPECT_GE(confirmed, runs * 9 / 10);
  EXPECT_GE(look_alikes, runs * 9 / 10);
  EXPECT_GE(rival_confirmed, look_alikes * 9 / 10);
  EXPECT_EQ(wrong_confirmed, 0);
}

// Along a featureless corridor a later scan fits a find and its rival 2 m on alike: both are
// confirmed, for the next scans to choose between; one the scan does not fit (turned) is not.
TEST(NearbyReset, ConfirmsBothOfTwoLookAlikesALaterScanFitsAlike) {
  OccupancyGrid corridor(800, 60, 0.05, Point2(0.0, 0.0));
  corridor.FillBox({0.0, 0.0}, {40.0, 0.1});
  corridor.FillBox({0.0, 2.9}, {40.0, 3.0});
  const LikelihoodField field(corridor);
  const GlobalScanSearch search(corridor, field);
  const RayCaster caster(corridor);
  const NearbyReset reset;
  const Pose2 found(15.0, 1.5, 0.0), rival(17.0, 1.5, 0.0), turned(20.0, 1.5, 0.8), step(0.6, 0.0, 0.0);
  const Pose2 found_at(0.0, 0.0, 0.0), now = found_at * step;
  const std::vector<Point2> points = ScanFrom(caster, found * step);
  const Pose2 estimate(16.0, 1.5, 0.6);  // lost: turned across the corridor
  const std::vector<Pose2> confirmed = reset.ConfirmWhereCarried(
      search, {{found, 0.95}, {{rival, 0.95}, {turned, 0.9}}}, found_at, now, estimate, points);
  // Each where it was carried (along a bare corridor, anywhere within the tolerance of 0.36 m).
  ASSERT_EQ(confirmed.size(), 2u);
  EXPECT_GT(Distance(confirmed[0].translation(), confirmed[1].translation()), 1.0);
  for (const Pose2& pose : confirmed) {
    const double off = std::min(Distance(pose.translation(), (found * step).translation()),
                                Distance(pose.translation(), (rival * step).translation()));
    EXPECT_LT(off, 0.4);
    EXPECT_NEAR(pose.y, 1.5, 0.05);
    EXPECT_NEAR(pose.theta, 0.0, 0.05);
  }
}

}  // namespace
}  // namespace navd::localization
