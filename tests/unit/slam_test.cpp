// The parts of graph SLAM: the correlative and point-to-line scan matchers, the SE(2) pose graph,
// and the errors SLAM is judged by.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <sstream>

#include "services/common/carmen_log.h"
#include "services/common/carmen_odometry.h"
#include "services/common/disc.h"
#include "services/common/error.h"
#include "services/common/ray_caster.h"
#include "services/common/relative_pose_error.h"
#include "services/common/trajectory_alignment.h"
#include "services/mapping/correlative_scan_matcher.h"
#include "services/mapping/graph_slam.h"
#include "services/mapping/line_fit.h"
#include "services/mapping/odometry_pairing.h"
#include "services/mapping/point_to_line_matcher.h"
#include "services/mapping/pose_graph.h"
#include "services/mapping/pose_graph_g2o.h"
#include "services/mapping/recycled_cells.h"
#include "services/mapping/scan_consistency.h"
#include "services/mapping/seen_through_check.h"
#include "services/mapping/shared_places.h"
#include "services/mapping/surface_facing_check.h"

namespace navd::mapping {
namespace {

// An L-shaped 8 x 6 m room with a pillar, 5 cm cells.
OccupancyGrid Room() {
  OccupancyGrid g(200, 160, 0.05, Point2::Zero());
  g.FillBox({0.0, 0.0}, {10.0, 0.1});
  g.FillBox({0.0, 7.9}, {10.0, 8.0});
  g.FillBox({0.0, 0.0}, {0.1, 8.0});
  g.FillBox({9.9, 0.0}, {10.0, 8.0});
  g.FillBox({6.0, 5.0}, {10.0, 8.0});
  g.FillBox({3.0, 3.0}, {3.6, 3.4});
  return g;
}

// A 360-beam scan of `map` from `pose`, ranges in the robot frame.
RangeScan ScanFrom(const OccupancyGrid& map, const Pose2& pose, std::mt19937* noise = nullptr) {
  const RayCaster caster(map);
  RangeScan scan;
  scan.angle_min = -M_PI;
  scan.angle_increment = 2.0 * M_PI / 360.0;
  std::normal_distribution<double> n(0.0, 0.01);
  for (int i = 0; i < 360; ++i) {
    const double a = pose.theta + scan.angle_min + i * scan.angle_increment;
    double r = caster.Cast(pose.translation(), a, 20.0);
    if (noise && r < 20.0) r += n(*noise);
    scan.ranges.push_back(static_cast<float>(r));
  }
  return scan;
}

std::vector<Point2> Points(const RangeScan& scan) {
  std::vector<Point2> out;
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    if (scan.ranges[i] >= 20.0f) continue;
    const double a = scan.angle_min + i * scan.angle_increment;
    out.emplace_back(scan.ranges[i] * std::cos(a), scan.ranges[i] * std::sin(a));
  }
  return out;
}

// A scan of more returns than the budget is thinned to no fewer than the budget and to about it
// (the widest spacing that keeps it), evenly along the wall; one within it keeps every return; one
// that the widest spacing still leaves above budget is thinned at that spacing.
TEST(CorrelativeScanMatcher, ThinsAScanToItsBudgetOfReturns) {
  std::vector<Point2> wall(1000);  // 1000 returns 2 mm apart along a 2 m wall
  for (int i = 0; i < 1000; ++i) wall[i] = Point2(1.0, -1.0 + 0.002 * i);
  const std::vector<Point2> thinned = ThinPointsTo(wall, 200, 0.1);
  EXPECT_GE(thinned.size(), 200u);
  EXPECT_LE(thinned.size(), 210u);
  for (size_t i = 1; i < thinned.size(); ++i) EXPECT_NEAR(thinned[i].y() - thinned[i - 1].y(), 0.01, 0.0011) << i;
  EXPECT_EQ(ThinPointsTo(wall, 1000, 0.1).size(), 1000u);
  EXPECT_EQ(ThinPointsTo(wall, 5, 0.1).size(), ThinPoints(wall, 0.1).size());
  EXPECT_TRUE(ThinPointsTo({}, 5, 0.1).empty());
}

TEST(RecycledCells, AGridGoneHandsItsMemoryToTheNextWhichStartsFromZeros) {
  // A dense cloud makes every cell of its grid nonzero; two points 3 m apart leave most of theirs 0.
  std::vector<Point2> cloud;
  for (double x = 0.0; x <= 3.0; x += 0.05)
    for (double y = 0.0; y <= 0.5; y += 0.05) cloud.emplace_back(x, y);
  for (size_t i = 0; i < RecycledCells::kKept; ++i) RecycledCells::Take(0);  // what earlier tests left
  const float* memory = nullptr;
  {
    const CorrelationGrid dense(cloud, 0.05, 0.05);
    memory = dense.Row(0);
    EXPECT_GT(dense.AtCell(dense.width() / 2, dense.height() / 2), 0.0f);
  }
  const CorrelationGrid sparse({{0.0, 0.0}, {3.0, 0.5}}, 0.05, 0.05);
  EXPECT_EQ(sparse.Row(0), memory);  // no larger than the dense grid: its memory holds it
  int nonzero = 0;
  for (int y = 0; y < sparse.height(); ++y)
    for (int x = 0; x < sparse.width(); ++x) nonzero += sparse.AtCell(x, y) > 0.0f;
  // Only the cells within 3 sigma of the two points: a disc of radius 3 cells each.
  EXPECT_GT(nonzero, 2 * 20);
  EXPECT_LT(nonzero, 2 * 40);
  EXPECT_EQ(sparse.AtCell(sparse.width() / 2, sparse.height() / 2), 0.0f);

  // Handed back dirty, a buffer comes out of Take as zeros; no more than kKept are kept.
  std::vector<float> dirty(1000, 7.0f);
  const float* dirty_memory = dirty.data();
  RecycledCells::Give(std::move(dirty));
  const std::vector<float> taken = RecycledCells::Take(800);
  EXPECT_EQ(taken.data(), dirty_memory);
  EXPECT_EQ(taken.size(), 800u);
  EXPECT_TRUE(std::all_of(taken.begin(), taken.end(), [](float v) { return v == 0.0f; }));
  std::vector<const float*> given;
  for (size_t i = 0; i < RecycledCells::kKept + 2; ++i) {
    std::vector<float> cells(100 + i);
    given.push_back(cells.data());
    RecycledCells::Give(std::move(cells));
  }
  std::vector<const float*> back;
  for (size_t i = 0; i < RecycledCells::kKept + 2; ++i) back.push_back(RecycledCells::Take(10).data());
  // The kKept roomiest come back, smallest first; then new memory.
  for (size_t i = 0; i < RecycledCells::kKept; ++i) EXPECT_EQ(back[i], given[i + 2]) << i;
}

TEST(CorrelativeScanMatcher, RecoversThePoseFromAnOffsetPrior) {
  const OccupancyGrid map = Room();
  const Pose2 reference_pose{2.0, 2.0, 0.3}, truth{2.6, 2.4, 0.5};
  std::vector<Point2> reference;
  for (const Point2& p : Points(ScanFrom(map, reference_pose))) reference.push_back(reference_pose * p);
  const CorrelationGrid grid(reference, 0.05, 0.05);
  const std::vector<Point2> scan = ThinPoints(Points(ScanFrom(map, truth)), 0.1);
  const Pose2 prior{truth.x + 0.15, truth.y - 0.12, truth.theta + 0.08};
  const ScanMatch m = MatchScan(grid, scan, prior, {});
  EXPECT_NEAR(m.pose.x, truth.x, 0.02);
  EXPECT_NEAR(m.pose.y, truth.y, 0.02);
  EXPECT_NEAR(m.pose.theta, truth.theta, 0.006);
  EXPECT_GT(m.score, 0.6);
  // Outside the window the true pose cannot be found: the score says so.
  const ScanMatch far = MatchScan(grid, scan, {truth.x + 1.0, truth.y, truth.theta}, {});
  EXPECT_LT(far.score, 0.6 * m.score);
}

// End points (robot frame) of 360 beams from `pose` to the nearest of `walls` (segments, world
// frame), with 1 cm of range noise: exact geometry, so only the noise limits a match.
std::vector<Point2> ScanOfWalls(const std::vector<std::pair<Point2, Point2>>& walls, const Pose2& pose,
                                std::mt19937& noise) {
  std::normal_distribution<double> n(0.0, 0.01);
  std::vector<Point2> out;
  for (int i = 0; i < 360; ++i) {
    const double a = -M_PI + i * M_PI / 180.0;
    const Point2 d = Rotate({1.0, 0.0}, pose.theta + a);
    double nearest = 1e9;
    for (const auto& [p, q] : walls) {
      // pose + t d = p + u (q - p), t > 0, u in [0, 1].
      const Point2 e = q - p, w = p - pose.translation();
      const double det = d.x() * -e.y() + e.x() * d.y();
      if (std::abs(det) < 1e-12) continue;
      const double t = (w.x() * -e.y() + e.x() * w.y()) / det, u = (d.x() * w.y() - d.y() * w.x()) / det;
      if (t > 0.0 && u >= 0.0 && u <= 1.0) nearest = std::min(nearest, t);
    }
    if (nearest < 20.0) out.emplace_back((nearest + n(noise)) * Point2(std::cos(a), std::sin(a)));
  }
  return out;
}

TEST(LineFit, FindsTheLineOfAWallAtAnyHeadingAndRefusesACorner) {
  // A wall at 30 degrees, 0.2 m from the point of interest, its points a little off it.
  const double heading = 0.5236;
  const Point2 along(std::cos(heading), std::sin(heading)), across(-along.y(), along.x());
  LineFit wall;
  for (int i = -5; i <= 5; ++i) wall.Add(0.2 * across + 0.03 * i * along + ((i % 2) ? 0.002 : -0.002) * across);
  const std::optional<FittedLine> line = wall.Fit(0.1);
  ASSERT_TRUE(line.has_value());
  EXPECT_NEAR(std::abs(line->normal.dot(across)), 1.0, 1e-3);
  EXPECT_NEAR(std::abs(line->mean.dot(line->normal)), 0.2, 1e-3);
  // The same along either axis: the closed form's two eigenvector choices.
  for (const Point2& direction : {Point2(1.0, 0.0), Point2(0.0, 1.0)}) {
    LineFit axis;
    for (int i = -3; i <= 3; ++i) axis.Add(0.05 * i * direction);
    const std::optional<FittedLine> fitted = axis.Fit(0.1);
    ASSERT_TRUE(fitted.has_value());
    EXPECT_NEAR(std::abs(fitted->normal.dot(direction)), 0.0, 1e-9);
  }
  // A corner's points spread as much one way as the other; one point, or the same point twice,
  // draws no line.
  LineFit corner;
  for (int i = 0; i <= 5; ++i) {
    corner.Add(Point2(0.03 * i, 0.0));
    corner.Add(Point2(0.0, 0.03 * i));
  }
  EXPECT_FALSE(corner.Fit(0.1).has_value());
  LineFit single;
  single.Add(Point2(0.1, 0.1));
  EXPECT_FALSE(single.Fit(0.1).has_value());
  single.Add(Point2(0.1, 0.1));
  EXPECT_FALSE(single.Fit(0.1).has_value());
}

TEST(PointToLineMatcher, PolishesTheCorrelativePoseBeyondItsCells) {
  // A 10 x 8 m room with a 2 m wall jutting in and a box.
  const std::vector<std::pair<Point2, Point2>> walls = {
      {{0, 0}, {10, 0}},  {{10, 0}, {10, 8}},     {{10, 8}, {0, 8}},      {{0, 8}, {0, 0}},  {{6, 8}, {6, 6}},
      {{3, 3}, {3.6, 3}}, {{3.6, 3}, {3.6, 3.4}}, {{3.6, 3.4}, {3, 3.4}}, {{3, 3.4}, {3, 3}}};
  std::mt19937 noise(7);
  const Pose2 reference_pose{2.0, 2.0, 0.3}, truth{2.63, 2.41, 0.517};
  std::vector<Point2> reference;
  for (const Point2& p : ScanOfWalls(walls, reference_pose, noise)) reference.push_back(reference_pose * p);
  const std::vector<Point2> scan = ThinPoints(ScanOfWalls(walls, truth, noise), 0.1);
  const Pose2 coarse = MatchScan(CorrelationGrid(reference, 0.05, 0.05), scan, {2.6, 2.4, 0.5}, {}).pose;
  const PointToLineResult fit = PointToLineMatcher(reference).Match(scan, coarse);
  ASSERT_TRUE(fit.ok);
  EXPECT_GT(fit.pairs, 100);
  EXPECT_LT(fit.rms, 0.02);
  const double error = Distance(fit.pose.translation(), truth.translation());
  const double heading_error = std::abs(NormalizeAngle(fit.pose.theta - truth.theta));
  // The correlative pose is off by millimetres and milliradians (its cells and angle steps).
  EXPECT_LT(error, 0.003);
  EXPECT_LT(heading_error, 0.001);
}

TEST(PointToLineMatcher, LeavesADirectionNoWallConstrainsWhereItStarted) {
  // Two parallel walls along x: a corridor says nothing about x.
  std::vector<Point2> reference, scan;
  for (double x = -5.0; x <= 5.0; x += 0.05) {
    reference.emplace_back(x, 1.0);
    reference.emplace_back(x, -1.0);
  }
  for (double x = -3.0; x <= 3.0; x += 0.1) {
    scan.emplace_back(x, 1.0);
    scan.emplace_back(x, -1.0);
  }
  const PointToLineResult fit = PointToLineMatcher(reference).Match(scan, {0.07, 0.04, 0.02});
  ASSERT_TRUE(fit.ok);
  EXPECT_NEAR(fit.pose.y, 0.0, 0.002);
  EXPECT_NEAR(fit.pose.theta, 0.0, 0.002);
  EXPECT_NEAR(fit.pose.x, 0.07, 0.01);
}

TEST(PointToLineMatcher, HoldsAScanToWallsOfAnyHeading) {
  // Two parallel walls 2 m apart, turned to each heading: a scan started 4 cm and 0.02 rad off
  // comes back across them, and stays where it started along them.
  for (const double heading : {0.0, 0.4, 1.2, M_PI / 2, 2.5, -0.8}) {
    const Pose2 turn{0.0, 0.0, heading};
    std::vector<Point2> reference, scan;
    for (double x = -5.0; x <= 5.0; x += 0.05) {
      reference.push_back(turn * Point2(x, 1.0));
      reference.push_back(turn * Point2(x, -1.0));
    }
    for (double x = -3.0; x <= 3.0; x += 0.1) {
      scan.emplace_back(x, 1.0);
      scan.emplace_back(x, -1.0);
    }
    const Pose2 start = turn * Pose2{0.03, 0.04, 0.02};
    const PointToLineResult fit = PointToLineMatcher(reference).Match(scan, start);
    ASSERT_TRUE(fit.ok) << heading;
    const Pose2 in_corridor = turn.inverse() * fit.pose;
    EXPECT_NEAR(in_corridor.y, 0.0, 0.002) << heading;
    EXPECT_NEAR(NormalizeAngle(in_corridor.theta), 0.0, 0.002) << heading;
    EXPECT_NEAR(in_corridor.x, 0.03, 0.01) << heading;
  }
}

TEST(PointToLineMatcher, RefusesWhenTooFewPointsPairWithALine) {
  // Scattered points have no lines; a scan far from the reference pairs with nothing.
  std::vector<Point2> scattered;
  scattered.reserve(50);
  for (int i = 0; i < 50; ++i) scattered.emplace_back(i * 0.5, (i % 7) * 0.45);
  std::vector<Point2> wall;
  for (double x = 0.0; x <= 3.0; x += 0.05) wall.emplace_back(x, 0.0);
  const Pose2 start{0.0, 0.01, 0.0};
  EXPECT_FALSE(PointToLineMatcher(scattered).Match(wall, start).ok);
  EXPECT_FALSE(PointToLineMatcher(wall).Match(wall, {0.0, 5.0, 0.0}).ok);
  EXPECT_FALSE(PointToLineMatcher({}).Match(wall, start).ok);
  EXPECT_TRUE(PointToLineMatcher(wall).Match(wall, start).ok);
}

TEST(PoseGraph, ALoopClosureRemovesTheOdometryDrift) {
  // A 4 x 4 m square driven in 16 steps; the odometry edges all turn 2 degrees too far per corner.
  std::vector<Pose2> truth;
  Pose2 p;
  for (int i = 0; i < 16; ++i) {
    truth.push_back(p);
    p = p * Pose2{1.0, 0.0, (i % 4 == 3) ? M_PI / 2 : 0.0};
  }
  PoseGraph graph;
  Pose2 estimate;
  std::vector<Pose2> steps;
  for (int i = 0; i < 16; ++i) {
    graph.AddNode(estimate);
    Pose2 step = truth[i].inverse() * truth[(i + 1) % 16];
    if (i % 4 == 3) step.theta += 2.0 * M_PI / 180.0;  // biased turn
    steps.push_back(step);
    estimate = estimate * step;
  }
  for (int i = 0; i + 1 < 16; ++i) graph.AddEdge({i, i + 1, steps[i], Eigen::Matrix3d::Identity() * 100.0, false});
  const double drift_before = Distance(graph.nodes()[15].translation(), truth[15].translation());
  EXPECT_GT(drift_before, 0.1);
  // The closure: node 15 seen from node 0 where it truly is.
  graph.AddEdge({0, 15, truth[0].inverse() * truth[15], Eigen::Matrix3d::Identity() * 1000.0, true});
  // A wrong closure, robust: it must not bend the map.
  graph.AddEdge({2, 10, Pose2{0.0, 0.0, 0.0}, Eigen::Matrix3d::Identity() * 1000.0, true});
  graph.Optimize();
  double worst = 0.0;
  for (int i = 0; i < 16; ++i)
    worst = std::max(worst, Distance(graph.nodes()[i].translation(), truth[i].translation()));
  EXPECT_LT(worst, 0.5 * drift_before) << "drift before " << drift_before;
  EXPECT_LT(Distance(graph.nodes()[15].translation(), truth[15].translation()), 0.05);
  EXPECT_NEAR(graph.nodes()[0].x, 0.0, 1e-9);  // the anchor stays
}

TEST(PoseGraph, SquaredErrorIsTheEdgesErrorWhitenedByItsInformation) {
  PoseGraph graph;
  graph.AddNode({0.0, 0.0, 0.0});
  graph.AddNode({1.1, 0.0, 0.02});
  const Eigen::Matrix3d information = Eigen::Vector3d(400.0, 400.0, 2500.0).asDiagonal();  // 5 cm, 0.02 rad
  // 0.1 m (2 sigma) and 0.02 rad (1 sigma) off a measured step of 1 m straight ahead.
  EXPECT_NEAR(graph.SquaredError({0, 1, Pose2{1.0, 0.0, 0.0}, information, true}), 4.0 + 1.0, 1e-9);
  EXPECT_NEAR(graph.SquaredError({0, 1, Pose2{1.1, 0.0, 0.02}, information, true}), 0.0, 1e-12);
}

TEST(PoseGraph, WritesG2osVerticesAndEdgesUnderTheIdsItIsGiven) {
  PoseGraph graph;
  graph.AddNode({0.0, 0.0, 0.0});
  graph.AddNode({1.0, 0.5, 0.25});
  Eigen::Matrix3d information;
  information << 400.0, 10.0, 1.5, 10.0, 100.0, -2.0, 1.5, -2.0, 2500.0;
  graph.AddEdge({0, 1, Pose2{1.0, 0.5, 0.25}, information, true});
  EXPECT_EQ(FormatG2o(graph, {7, 42}),
            "VERTEX_SE2 7 0.000000 0.000000 0.000000000\n"
            "VERTEX_SE2 42 1.000000 0.500000 0.250000000\n"
            "EDGE_SE2 7 42 1.000000 0.500000 0.250000000 400 10 1.5 100 -2 2500\n");
  try {
    FormatG2o(graph, {7});
    FAIL() << "one id for two nodes was taken";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(e.what()).find("1 for 2 nodes"), std::string::npos) << e.what();
  }
}

// Feeds `slam` a scan at each true pose with odometry 5 % and 2 degrees per metre off each step.
void AddWithNoisyOdometry(GraphSlam& slam, const std::vector<Pose2>& truth, std::mt19937& rng,
                          const std::function<RangeScan(const Pose2&)>& scan_at) {
  std::normal_distribution<double> n(0.0, 1.0);
  Pose2 odometry = truth.front();
  for (size_t i = 0; i < truth.size(); ++i) {
    if (i > 0) {
      const Pose2 step = truth[i - 1].inverse() * truth[i];
      const double d = std::hypot(step.x, step.y);
      odometry = odometry * Pose2{step.x * (1.0 + 0.05 * n(rng)), step.y, step.theta + 0.035 * d * n(rng)};
    }
    slam.AddScan(odometry, scan_at(truth[i]));
  }
}

// Once round the room in 0.4 m steps: the true poses.
std::vector<Pose2> OneLap() {
  std::vector<Pose2> truth;
  const std::vector<Point2> corners{{1.5, 1.5}, {8.5, 1.5}, {8.5, 4.0}, {4.5, 4.0}, {4.5, 6.5}, {1.5, 6.5}};
  for (size_t c = 0; c < corners.size(); ++c) {
    const Point2 &a = corners[c], &b = corners[(c + 1) % corners.size()];
    const double heading = std::atan2(b.y() - a.y(), b.x() - a.x());
    const int steps = static_cast<int>(Distance(a, b) / 0.4);
    for (int k = 0; k < steps; ++k) {
      const Point2 q = a + (b - a) * (double(k) / steps);
      truth.emplace_back(q.x(), q.y(), heading);
    }
  }
  return truth;
}

// Round the room twice, 0.4 m steps, odometry 5% and 2 degrees per metre off: the true poses.
std::vector<Pose2> DriveTwoLaps(const OccupancyGrid& map, GraphSlam& slam) {
  std::mt19937 rng(5);
  std::vector<Pose2> truth = OneLap();
  const size_t lap = truth.size();
  for (size_t i = 0; i < lap; ++i) truth.push_back(truth[i]);
  AddWithNoisyOdometry(slam, truth, rng, [&](const Pose2& pose) { return ScanFrom(map, pose, &rng); });
  return truth;
}

GraphSlamOptions RoomSlamOptions() {
  GraphSlamOptions o;
  o.first_pose = {1.5, 1.5, 0.0};
  o.loop_min_node_gap = 20;
  return o;
}

double PositionRmse(const std::vector<Pose2>& estimate, const std::vector<Pose2>& truth) {
  double sq = 0.0;
  for (size_t i = 0; i < truth.size(); ++i)
    sq += std::pow(Distance(estimate[i].translation(), truth[i].translation()), 2);
  return std::sqrt(sq / truth.size());
}

TEST(GraphSlam, MapsARoomFromNoisyOdometryAndClosesTheLoop) {
  const OccupancyGrid map = Room();
  GraphSlam slam(RoomSlamOptions());
  const std::vector<Pose2> truth = DriveTwoLaps(map, slam);
  const std::vector<Pose2> estimate = slam.Trajectory();
  ASSERT_EQ(estimate.size(), truth.size());
  EXPECT_LT(PositionRmse(estimate, truth), 0.05);
  EXPECT_GE(slam.loop_closures(), 1);
  // The map: the pillar's cells are occupied where the truth has them, the room's middle free.
  MapperOptions mo;
  const OccupancyGrid built = slam.RenderMap(mo);
  EXPECT_TRUE(built.IsOccupied(built.CellOf({3.0, 3.2})) || built.IsOccupied(built.CellOf({3.05, 3.2})));
  EXPECT_GE(built.at(built.CellOf({5.0, 2.0})), 0);
  EXPECT_LT(built.at(built.CellOf({5.0, 2.0})), 20);
}

TEST(SeenThroughCheck, ABeamReadingBeyondAPlaceSawThroughItButNotAWallItsEdgeOrAWallGrazed) {
  const OccupancyGrid map = Room();
  const Pose2 pose{1.5, 1.5, 0.0};
  const RangeScan scan = ScanFrom(map, pose);
  const SeenThroughCheck check(pose, scan.ranges, scan.angle_min, scan.angle_increment, 20.0);
  EXPECT_TRUE(check.SawThrough({5.0, 1.5}));  // free, the wall 4.9 m behind it
  EXPECT_TRUE(check.SawThrough({2.0, 5.0}));
  EXPECT_FALSE(check.SawThrough({9.92, 1.5}));  // on the far wall
  EXPECT_FALSE(check.SawThrough({12.0, 1.5}));  // behind it
  EXPECT_FALSE(check.SawThrough({3.0, 3.0}));   // the pillar's corner: beams on one side hit it
  EXPECT_FALSE(check.SawThrough({3.0, 3.2}));   // its face
  EXPECT_FALSE(check.SawThrough({3.3, 3.7}));   // behind it, in its shadow
  EXPECT_FALSE(check.SawThrough({1.6, 1.6}));   // nearer than min_distance
  // The bottom wall seen at 2-4 degrees from 0.3 m above it.
  const Pose2 low{1.5, 0.4, 0.0};
  const RangeScan grazing = ScanFrom(map, low);
  const SeenThroughCheck along(low, grazing.ranges, grazing.angle_min, grazing.angle_increment, 20.0);
  for (double x = 5.0; x < 9.0; x += 0.25) EXPECT_FALSE(along.SawThrough({x, 0.1})) << x;
  // No-returns say nothing of what lies along them.
  RangeScan open = scan;
  std::fill(open.ranges.begin(), open.ranges.end(), 20.0f);
  EXPECT_FALSE(SeenThroughCheck(pose, open.ranges, open.angle_min, open.angle_increment, 20.0).SawThrough({5.0, 1.5}));
}

// The beams within the span (2 degrees) either side judge a place, whatever the scanner's spacing:
// 4 either side at half a degree, 2 at one degree.
TEST(SeenThroughCheck, JudgesTheSameSweepWhateverTheBeamSpacing) {
  for (const int beams : {361, 181}) {
    const double increment = M_PI / (beams - 1);
    const size_t ahead = static_cast<size_t>(beams / 2), side = beams == 361 ? 4 : 2;
    std::vector<float> ranges(static_cast<size_t>(beams), 10.0f);
    const Pose2 pose;
    EXPECT_TRUE(SeenThroughCheck(pose, ranges, -M_PI / 2, increment, 20.0).SawThrough({3.0, 0.0})) << beams;
    ranges[ahead + side] = 2.0f;  // the last beam within the span hits something nearer than the place
    EXPECT_FALSE(SeenThroughCheck(pose, ranges, -M_PI / 2, increment, 20.0).SawThrough({3.0, 0.0})) << beams;
    ranges[ahead + side] = 10.0f;
    ranges[ahead + side + 1] = 2.0f;  // the first beyond it does not count
    EXPECT_TRUE(SeenThroughCheck(pose, ranges, -M_PI / 2, increment, 20.0).SawThrough({3.0, 0.0})) << beams;
  }
}

// A scanner sweeping a whole turn from 0 has beams on both sides of its seam: a place just
// clockwise of its first beam is judged by the last beams and the first.
TEST(SeenThroughCheck, JudgesAPlaceAcrossAWholeTurnScannersSeam) {
  std::vector<float> ranges(360, 10.0f);
  const double increment = 2.0 * M_PI / 360.0;
  const Pose2 pose;
  const Point2 place(3.0 * std::cos(-increment), 3.0 * std::sin(-increment));  // beam 359
  EXPECT_TRUE(SeenThroughCheck(pose, ranges, 0.0, increment, 20.0).SawThrough(place));
  ranges[1] = 2.0f;  // two beams on, across the seam
  EXPECT_FALSE(SeenThroughCheck(pose, ranges, 0.0, increment, 20.0).SawThrough(place));
  // Beams spread too finely to count, or no spacing at all, see through nothing.
  ranges[1] = 10.0f;
  EXPECT_FALSE(SeenThroughCheck(pose, ranges, 0.0, 1e-300, 20.0).SawThrough(place));
  EXPECT_FALSE(SeenThroughCheck(pose, ranges, 0.0, std::nan(""), 20.0).SawThrough(place));
}

TEST(SharedPlaces, RefusesARadiusThatIsNoDistanceAndSoDoesGraphSlamWhenItWouldUseIt) {
  EXPECT_THROW(SharedPlaces(0.0), Error);
  EXPECT_THROW(SharedPlaces(std::nan("")), Error);
  GraphSlamOptions o;
  o.seen_through_support = 0.0;
  EXPECT_NO_THROW(GraphSlam{o});  // off: never used
  o.drop_seen_through = true;
  EXPECT_THROW(GraphSlam{o}, Error);
}

TEST(SharedPlaces, APlaceIsSharedWhenAnotherScansPointLiesNearIt) {
  SharedPlaces places(0.15);
  places.Add({0.0, 0.0}, 1);
  places.Add({1.0, 0.0}, 2);
  places.Add({-0.14, 0.0}, 3);
  EXPECT_FALSE(places.SeenByAnother({1.05, 0.0}, 2));  // its own point only
  EXPECT_TRUE(places.SeenByAnother({1.05, 0.05}, 1));
  EXPECT_TRUE(places.SeenByAnother({0.0, 0.1}, 3));
  EXPECT_FALSE(places.SeenByAnother({0.5, 0.0}, 1));
  EXPECT_FALSE(places.SeenByAnother({0.0, 0.2}, 2));
  places.Add({-0.01, -0.01}, 4);
  EXPECT_TRUE(places.SeenByAnother({0.01, 0.01}, 5));  // across both axes' cell edges at 0
}

// Two laps of the room while a person walks back and forth across its lower half: the returns
// the person left in the nodes' scans are dropped from the references, the walls and the pillar
// are not.
TEST(GraphSlam, LeavesOutTheReturnsOfAPersonWalkingPastButNoWall) {
  const OccupancyGrid map = Room();
  const std::vector<Pose2> lap = OneLap();
  std::vector<Pose2> truth = lap;
  truth.insert(truth.end(), lap.begin(), lap.end());
  // 0.8 s per scan; the person walks y = 2.7 between x = 5 and 8.5 at 0.8 m/s.
  auto person_at = [](size_t scan) {
    const double along = std::fmod(0.64 * static_cast<double>(scan), 7.0);
    return Disc{{5.0 + (along < 3.5 ? along : 7.0 - along), 2.7}, 0.2, 1};
  };
  for (const bool walking : {false, true}) {
    std::mt19937 rng(5);
    GraphSlamOptions o = RoomSlamOptions();
    o.drop_seen_through = true;
    GraphSlam slam(o);
    size_t scan = 0;
    AddWithNoisyOdometry(slam, truth, rng, [&](const Pose2& pose) {
      RangeScan s = ScanFrom(map, pose, &rng);
      const Disc person = person_at(scan++);
      for (size_t i = 0; walking && i < s.ranges.size(); ++i) {
        const double a = pose.theta + s.angle_min + i * s.angle_increment;
        const double r = RayDiscDistance(pose.translation(), {std::cos(a), std::sin(a)}, person);
        s.ranges[i] = static_cast<float>(std::min<double>(s.ranges[i], r));
      }
      return s;
    });
    EXPECT_LT(PositionRmse(slam.Trajectory(), truth), 0.05) << walking;
    const std::vector<Point2> left_out = slam.SeenThroughPoints();
    if (!walking) {
      EXPECT_TRUE(left_out.empty()) << left_out.size() << " wall points left out, the first at "
                                    << left_out.front().transpose();
      continue;
    }
    EXPECT_GE(left_out.size(), 20u);
    for (const Point2& p : left_out) {
      EXPECT_NEAR(p.y(), 2.7, 0.3) << p.transpose();
      EXPECT_GT(p.x(), 4.7) << p.transpose();
      EXPECT_LT(p.x(), 8.8) << p.transpose();
    }
  }
}

// Scans metres apart (a decimated log) carry odometry errors beyond the base window: the front end's
// window widens with the step, so the match still finds the scan's true pose.
TEST(GraphSlam, ClosuresThatAgreeWithTheGraphAreOptimisedTogether) {
  // Three laps of the room: from the second on, nearly every node closes a loop on a place already
  // mapped, within a fraction of a sigma of the graph.
  const OccupancyGrid map = Room();
  const std::vector<Pose2> lap = OneLap();
  std::vector<Pose2> truth;
  for (int k = 0; k < 3; ++k) truth.insert(truth.end(), lap.begin(), lap.end());
  auto drive = [&](const GraphSlamOptions& options, std::vector<Pose2>* estimate) {
    auto slam = std::make_unique<GraphSlam>(options);
    std::mt19937 rng(5);
    AddWithNoisyOdometry(*slam, truth, rng, [&](const Pose2& pose) { return ScanFrom(map, pose, &rng); });
    *estimate = slam->Trajectory();
    return slam;
  };
  GraphSlamOptions each = RoomSlamOptions();
  each.loop_settled_error = 0.0;
  std::vector<Pose2> batched_estimate, each_estimate;
  const auto batched = drive(RoomSlamOptions(), &batched_estimate);
  const auto every = drive(each, &each_estimate);
  EXPECT_GE(every->loop_closures(), 2 * static_cast<int>(lap.size()));
  EXPECT_EQ(every->optimisations(), every->loop_closures());
  EXPECT_GE(batched->loop_closures(), 2 * static_cast<int>(lap.size()));
  EXPECT_LT(batched->optimisations(), batched->loop_closures() / 4);
  EXPECT_GE(batched->optimisations(), 1);  // the first closure back at the start pulls the lap round
  EXPECT_LT(PositionRmse(batched_estimate, truth), 0.05);
  EXPECT_LT(PositionRmse(batched_estimate, truth), PositionRmse(each_estimate, truth) + 0.01);
  std::printf("batched: %d of %d closures optimised, RMSE %.4f m; each: RMSE %.4f m\n", batched->optimisations(),
              batched->loop_closures(), PositionRmse(batched_estimate, truth), PositionRmse(each_estimate, truth));
}

TEST(GraphSlam, FrontEndFindsAScanMetresAwayWhoseOdometryIsOffByMoreThanTheBaseWindow) {
  const OccupancyGrid map = Room();
  std::mt19937 rng(3);
  GraphSlamOptions o = RoomSlamOptions();
  o.first_pose = {2.0, 2.0, 0.0};
  const Pose2 truth{4.5, 2.3, 0.0};
  const Pose2 odometry{4.5 + 0.35, 2.3 - 0.1, 0.2};  // 0.36 m and 0.2 rad off after a 2.5 m step
  ASSERT_GT(0.36, o.sequential.window_xy);
  ASSERT_GT(0.2, o.sequential.window_theta);
  GraphSlam slam(o);
  slam.AddScan({2.0, 2.0, 0.0}, ScanFrom(map, o.first_pose, &rng));
  const Pose2 found = slam.AddScan(odometry, ScanFrom(map, truth, &rng));
  EXPECT_LT(Distance(found.translation(), truth.translation()), 0.05);
  EXPECT_LT(std::abs(NormalizeAngle(found.theta - truth.theta)), 0.02);
}

// Odometry noisier than the default turns 0.3 rad off over a 1.5 m step, beyond the window the
// default noise model (3 x 0.035 rad/m) opens: told the noise, the front end widens its window
// that much and finds the scan's true heading; told the default, it cannot.
TEST(GraphSlam, FrontEndWindowWidensWithTheOdometryNoiseItIsTold) {
  const OccupancyGrid map = Room();
  const Pose2 start{2.0, 2.0, 0.0}, truth{3.5, 2.2, 0.0};
  const Pose2 odometry{3.5, 2.2, 0.3};
  auto heading_error = [&](const OdometryNoise& noise) {
    std::mt19937 rng(5);
    GraphSlamOptions o = RoomSlamOptions();
    o.first_pose = start;
    o.odometry = noise;
    GraphSlam slam(o);
    slam.AddScan(start, ScanFrom(map, start, &rng));
    return std::abs(NormalizeAngle(slam.AddScan(odometry, ScanFrom(map, truth, &rng)).theta - truth.theta));
  };
  const OdometryNoise defaults;
  ASSERT_LT(std::max(GraphSlamOptions().sequential.window_theta, 3.0 * defaults.rotation_per_metre * 1.5), 0.3);
  EXPECT_GT(heading_error(defaults), 0.05);
  EXPECT_LT(heading_error({defaults.translation, 0.08}), 0.02);
}

// One lap whose odometry turns `jump` rad too far between scans 9 and 10 (wheels slipping) and
// is exact otherwise, into `slam`: the true poses.
std::vector<Pose2> LapWithAnOdometryJump(GraphSlam& slam, double jump) {
  const OccupancyGrid map = Room();
  std::mt19937 rng(4);
  std::vector<Pose2> truth = OneLap();
  Pose2 odometry = truth.front();
  for (size_t i = 0; i < truth.size(); ++i) {
    if (i > 0) odometry = odometry * (truth[i - 1].inverse() * truth[i]);
    if (i == 10) odometry = odometry * Pose2(0.0, 0.0, jump);
    slam.AddScan(odometry, ScanFrom(map, truth[i], &rng));
  }
  return truth;
}

// Beyond the front end's ±0.15 rad window scan 10 is found again by the wider search and held;
// scan 11, needing about the same correction, confirms it, and both keep their true poses.
TEST(GraphSlam, FrontEndRecoveryFollowsOdometryThatErrsBeyondTheWindow) {
  ASSERT_GT(0.3, GraphSlamOptions().sequential.window_theta);
  for (const double jump : {0.3, 0.45}) {
    GraphSlamOptions o = RoomSlamOptions();
    o.front_recovery.below_score = 0.6;
    GraphSlam slam(o);
    const std::vector<Pose2> truth = LapWithAnOdometryJump(slam, jump);
    EXPECT_EQ(slam.nodes(), static_cast<int>(truth.size()) - 1) << "one scan held, jump " << jump;
    const std::vector<Pose2> estimate = slam.Trajectory();
    ASSERT_EQ(estimate.size(), truth.size());
    for (size_t i = 0; i < truth.size(); ++i) {
      EXPECT_LT(Distance(estimate[i].translation(), truth[i].translation()), 0.05) << "scan " << i << ", " << jump;
      EXPECT_LT(std::abs(NormalizeAngle(estimate[i].theta - truth[i].theta)), 0.02) << "scan " << i << ", " << jump;
    }
  }
  GraphSlam off(RoomSlamOptions());  // the chain turns away at scan 10
  const std::vector<Pose2> truth = LapWithAnOdometryJump(off, 0.4);
  EXPECT_GT(PositionRmse(off.Trajectory(), truth), 0.2);
}

TEST(GraphSlam, FrontEndRecoveryRefusesOptionsThatCannotSearch) {
  GraphSlamOptions o;
  o.front_recovery.gate_angle_step_factor = 0.0;
  EXPECT_THROW(GraphSlam{o}, Error);
}

// A scan that fits 0.4 rad from where exact odometry puts it, once (its own stamp or pose off), is
// held back; the next scan matches where the odometry puts it, so the held one is dropped and the
// chain does not follow it.
TEST(GraphSlam, FrontEndRecoveryDropsAScanThatFitsFarFromItsOdometryOnce) {
  const OccupancyGrid map = Room();
  std::mt19937 rng(4);
  GraphSlamOptions o = RoomSlamOptions();
  o.front_recovery.below_score = 0.6;
  GraphSlam slam(o);
  const std::vector<Pose2> truth = OneLap();
  for (size_t i = 0; i < truth.size(); ++i) {
    const Pose2 seen_from = i == 10 ? truth[i] * Pose2(0.0, 0.0, 0.4) : truth[i];
    slam.AddScan(truth[i], ScanFrom(map, seen_from, &rng));
  }
  EXPECT_EQ(slam.nodes(), static_cast<int>(truth.size()) - 1);
  const std::vector<Pose2> estimate = slam.Trajectory();
  ASSERT_EQ(estimate.size(), truth.size());
  for (size_t i = 0; i < truth.size(); ++i) {
    EXPECT_LT(Distance(estimate[i].translation(), truth[i].translation()), 0.05) << "scan " << i;
    EXPECT_LT(std::abs(NormalizeAngle(estimate[i].theta - truth[i].theta)), 0.02) << "scan " << i;
  }
}

// The information (1/m²) of the front end's edge for a second scan 0.5 m on from `from`, along
// `direction` (the new node's frame).
double SequentialInformationAlong(const OccupancyGrid& map, const Pose2& from, const Point2& direction) {
  std::mt19937 rng(5);
  GraphSlamOptions o;
  o.first_pose = from;
  GraphSlam slam(o);
  const Pose2 step(0.5, 0.0, 0.0), to = from * step;
  slam.AddScan(Pose2(), ScanFrom(map, from, &rng));
  slam.AddScan(step, ScanFrom(map, to, &rng));
  const Eigen::Matrix3d& information = slam.graph().edges().back().information;
  return direction.dot(information.topLeftCorner<2, 2>() * direction);
}

// Along a bare corridor (its ends beyond the laser's 20 m) the walls say nothing of how far the
// robot went, so the front end's edge there is as uncertain as the odometry's prior (0.1 m), and
// across it about as certain as a match in a room (the base 0.03 m and the match's own
// uncertainty, a few centimetres, added): a loop closure then stretches the chain along the
// corridor instead of bending it.
TEST(GraphSlam, TheFrontEndsEdgeIsWeakAlongACorridorAndFirmAcrossIt) {
  OccupancyGrid corridor(1000, 60, 0.05, Point2::Zero());
  corridor.FillBox({0.0, 0.0}, {50.0, 0.1});
  corridor.FillBox({0.0, 2.9}, {50.0, 3.0});
  const double heading = 0.3;  // the robot drives at an angle to the corridor
  const Pose2 from(22.0, 1.2, heading);
  const Point2 along(std::cos(-heading), std::sin(-heading)), across(-along.y(), along.x());  // node frame
  const double firm = 1.0 / (0.03 * 0.03), free = 1.0 / (0.1 * 0.1);
  EXPECT_LT(SequentialInformationAlong(corridor, from, along), 1.2 * free);
  EXPECT_GT(SequentialInformationAlong(corridor, from, across), 0.4 * firm);
  EXPECT_LT(SequentialInformationAlong(corridor, from, across), firm);
  const OccupancyGrid room = Room();
  EXPECT_GT(SequentialInformationAlong(room, Pose2(1.5, 1.5, heading), along), 0.4 * firm);
  EXPECT_GT(SequentialInformationAlong(room, Pose2(1.5, 1.5, heading), across), 0.4 * firm);
}

TEST(GraphSlam, RefineMatchesEachNodeAgainstTheLapBeforeAndKeepsTheTrajectory) {
  const OccupancyGrid map = Room();
  GraphSlam slam(RoomSlamOptions());
  const std::vector<Pose2> truth = DriveTwoLaps(map, slam);
  const double before = PositionRmse(slam.Trajectory(), truth);
  const size_t nodes = slam.nodes();
  slam.Refine();
  // The second lap passes the first everywhere: most of its nodes get a match, each one true.
  EXPECT_GE(slam.refinements().size(), nodes / 4);
  for (const LoopClosure& c : slam.refinements()) {
    const Pose2 diff = (truth[c.from_scan].inverse() * truth[c.to_scan]).inverse() * c.measurement;
    EXPECT_LT(std::hypot(diff.x, diff.y), 0.1) << c.from_scan << " -> " << c.to_scan;
    EXPECT_LT(std::abs(diff.theta), 0.05) << c.from_scan << " -> " << c.to_scan;
  }
  EXPECT_LT(PositionRmse(slam.Trajectory(), truth), std::max(before, 0.03) * 1.1);
}

// Scans taken round the room agree at their true poses to about their range noise (1 cm); a scan
// placed 6 cm off stands out, and makes the whole trajectory score worse.
TEST(ScanConsistency, ScansAgreeAtTheirTruePosesAndAScanPlacedOffStandsOut) {
  const OccupancyGrid map = Room();
  std::mt19937 rng(4);
  const std::vector<Pose2> truth = OneLap();
  std::vector<std::vector<Point2>> returns;
  returns.reserve(truth.size());
  for (const Pose2& pose : truth) returns.push_back(Points(ScanFrom(map, pose, &rng)));
  const ScanConsistencyResult right = ScanConsistency(truth, returns).Score();
  EXPECT_GT(right.scored, static_cast<long long>(truth.size()) * 100);
  EXPECT_LT(right.mean_distance, 0.012);
  std::vector<Pose2> moved = truth;
  const size_t off = truth.size() / 2;
  moved[off] = moved[off] * Pose2(0.0, 0.06, 0.0);
  const ScanConsistencyResult wrong = ScanConsistency(moved, returns).Score();
  EXPECT_GT(wrong.scan_mean_distance[off], 0.03);
  EXPECT_LT(right.scan_mean_distance[off], 0.015);
  EXPECT_GT(wrong.mean_distance, right.mean_distance);
  // The other scans tell where the one placed off belongs: back where it was taken, it fits best.
  const ScanConsistency placed_off(moved, returns);
  EXPECT_LT(placed_off.ScanAt(off, truth[off]).mean_distance, 0.5 * placed_off.ScanAt(off, moved[off]).mean_distance);
  // A scan alone has nothing to agree with; poses and scans must pair up.
  const ScanConsistencyResult alone = ScanConsistency({truth[0]}, {returns[0]}).Score();
  EXPECT_EQ(alone.scored, 0);
  EXPECT_TRUE(std::isnan(alone.mean_distance));
  EXPECT_TRUE(std::isnan(alone.scan_mean_distance[0]));
  try {
    [[maybe_unused]] const ScanConsistency refused(truth, {returns[0]});
    FAIL() << "a trajectory longer than its scans was scored";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
  }
}

// A 180-degree, 1-degree scan of `map` from `pose` (as the logs' SICK scanners); no return reads 81.91.
RangeScan FrontScanFrom(const OccupancyGrid& map, const Pose2& pose, std::mt19937* noise) {
  const RayCaster caster(map);
  RangeScan scan;
  scan.angle_min = -M_PI / 2;
  scan.angle_increment = M_PI / 180.0;
  scan.range_max = 81.91;
  std::normal_distribution<double> n(0.0, 0.01);
  for (int i = 0; i < 180; ++i) {
    const double r = caster.Cast(pose.translation(), pose.theta + scan.angle_min + i * scan.angle_increment, 30.0);
    scan.ranges.push_back(static_cast<float>(r < 30.0 ? r + n(*noise) : 81.91));
  }
  return scan;
}

// Down a bare corridor and back the other way with a 180-degree scanner: each pass sees the end
// wall it faces, and the two have only the side walls beside the robot in common. Refinement holds
// the way back to the way out there, across the corridor, and leaves the position along it to the
// chain.
TEST(GraphSlam, RefineHoldsAPassTheOtherWayAcrossTheCorridorNotAlongIt) {
  OccupancyGrid corridor(260, 60, 0.05, Point2::Zero());
  corridor.FillBox({0.0, 0.0}, {13.0, 0.1});
  corridor.FillBox({0.0, 2.4}, {13.0, 2.5});
  corridor.FillBox({0.0, 0.0}, {0.1, 2.5});
  corridor.FillBox({12.9, 0.0}, {13.0, 2.5});
  std::vector<Pose2> truth;
  for (double x = 1.5; x < 11.0; x += 0.4) truth.emplace_back(x, 1.3, 0.0);
  const size_t out = truth.size();
  for (int k = 1; k <= 4; ++k) truth.emplace_back(truth.back().x, 1.3, k * M_PI / 4);
  for (double x = truth.back().x - 0.4; x > 1.4; x -= 0.4) truth.emplace_back(x, 1.1, M_PI);
  GraphSlamOptions o;
  o.first_pose = truth.front();
  GraphSlam slam(o);
  std::mt19937 rng(3);
  AddWithNoisyOdometry(slam, truth, rng, [&](const Pose2& pose) { return FrontScanFrom(corridor, pose, &rng); });
  ASSERT_EQ(slam.nodes(), static_cast<int>(truth.size()));  // every scan a node: their indices agree
  const size_t kept = slam.graph().edges().size();
  slam.Refine();
  int back_to_out = 0;
  for (size_t e = kept; e < slam.graph().edges().size(); ++e) {
    const PoseGraphEdge& edge = slam.graph().edges()[e];
    const int from = edge.from;
    if (from >= static_cast<int>(out) || edge.to <= static_cast<int>(out) + 4) continue;
    ++back_to_out;
    // The node's frame faces back down the corridor: x along it, y across.
    const Pose2 measured = edge.measurement;
    const Pose2 right = truth[from].inverse() * truth[edge.to];
    const Pose2 diff = right.inverse() * measured;
    EXPECT_LT(std::abs(diff.y), 0.03) << from << " -> " << edge.to;
    EXPECT_LT(std::abs(diff.theta), 0.02) << from << " -> " << edge.to;
    EXPECT_LT(edge.information(0, 0), 0.2 * edge.information(1, 1)) << from << " -> " << edge.to;
  }
  EXPECT_GE(back_to_out, 5);
}

std::vector<PlacedReturns> Placed(const std::vector<Pose2>& poses, const std::vector<std::vector<Point2>>& points) {
  std::vector<PlacedReturns> out;
  for (size_t i = 0; i < poses.size(); ++i) out.push_back({poses[i], &points[i]});
  return out;
}

TEST(SurfaceFacingCheck, ARightMatchSeesTheWallsFromTheReferencesSideAndAThinWallFromEither) {
  OccupancyGrid map = Room();
  map.FillBox({0.0, 4.0}, {5.0, 4.1});  // a 10 cm partition, seen from both sides below
  std::mt19937 rng(2);
  const std::vector<Pose2> reference_poses{{2.0, 2.0, 0.3}, {2.0, 6.0, -0.4}};
  const std::vector<std::vector<Point2>> reference{Points(ScanFrom(map, reference_poses[0], &rng)),
                                                   Points(ScanFrom(map, reference_poses[1], &rng))};
  const SurfaceFacingCheck check(Placed(reference_poses, reference));
  for (const Pose2& truth : {Pose2{2.6, 2.4, 0.5}, Pose2{1.5, 5.0, 2.0}}) {
    EXPECT_LT(check.BehindShare(truth, Points(ScanFrom(map, truth, &rng))), 0.05);
  }
}

// A corridor's outer corner (the robot inside it) laid on the inner corner of the block the
// corridor runs round, which the reference saw from outside: every wall fits, each from behind.
TEST(SurfaceFacingCheck, AnOuterCornerLaidOnAnInnerOneIsSeenFromBehind) {
  OccupancyGrid map(240, 240, 0.05, Point2::Zero());
  map.FillBox({0.0, 0.0}, {12.0, 0.1});  // the corridor's outer walls
  map.FillBox({0.0, 0.0}, {0.1, 12.0});
  map.FillBox({3.0, 3.0}, {12.0, 12.0});  // the block the corridor runs round
  std::mt19937 rng(4);
  const Pose2 reference_pose{1.5, 1.5, 0.0}, truth{1.5, 1.5, -M_PI / 2};
  const std::vector<std::vector<Point2>> reference{Points(ScanFrom(map, reference_pose, &rng))};
  const SurfaceFacingCheck check(Placed({reference_pose}, reference));
  const std::vector<Point2> scan = Points(FrontScanFrom(map, truth, &rng));
  EXPECT_LT(check.BehindShare(truth, scan), 0.05);
  EXPECT_GT(check.BehindShare({4.5, 4.5, -M_PI / 2}, scan), 0.9);  // slid by the corridor's width both ways
}

// A loop of 3 m corridors round a 34 x 6 m block, driven 1.3 times from a corner, with door
// recesses (0.9 m wide, 0.3 m deep, unevenly spaced) in the walls: nothing closes until the robot
// is back at the start, where a scan looking into the start's corner fits the block's corner, 3 m
// across and 3 m along, as well as its own.
OccupancyGrid CorridorLoop() {
  OccupancyGrid g(820, 260, 0.05, Point2::Zero());
  g.FillBox({0.0, 0.0}, {41.0, 0.5});  // outer walls, 0.5 m thick
  g.FillBox({0.0, 12.5}, {41.0, 13.0});
  g.FillBox({0.0, 0.0}, {0.5, 13.0});
  g.FillBox({40.5, 0.0}, {41.0, 13.0});
  g.FillBox({3.5, 3.5}, {37.5, 9.5});  // the block
  const double gaps[] = {7.0, 11.0, 9.0, 13.0, 6.0, 10.0, 8.0, 12.0};
  int k = 0;
  for (double x = 6.0; x < 34.0; x += gaps[k++ % 8]) {
    g.FillBox({x, 0.2}, {x + 0.9, 0.5}, OccupancyGrid::kFree);
    g.FillBox({x + 1.5, 3.5}, {x + 2.4, 3.8}, OccupancyGrid::kFree);
    g.FillBox({x + 3.0, 12.5}, {x + 3.9, 12.8}, OccupancyGrid::kFree);
    g.FillBox({x + 4.5, 9.2}, {x + 5.4, 9.5}, OccupancyGrid::kFree);
  }
  return g;
}

TEST(GraphSlam, BackAtTheStartOfACorridorLoopItClosesOnTheRightCornerNotTheBlocksCorner) {
  const OccupancyGrid map = CorridorLoop();
  std::mt19937 rng(6);
  std::vector<Pose2> truth;
  const std::vector<Point2> corners{{2.0, 2.0}, {39.0, 2.0}, {39.0, 11.0}, {2.0, 11.0}};
  for (int leg = 0; leg < 6; ++leg) {
    const Point2 &a = corners[leg % 4], &b = corners[(leg + 1) % 4];
    const double heading = std::atan2(b.y() - a.y(), b.x() - a.x());
    if (!truth.empty()) {  // turn on the spot
      const double from = truth.back().theta, turn = NormalizeAngle(heading - from);
      for (int i = 1; i <= 5; ++i) truth.emplace_back(a.x(), a.y(), from + turn * i / 6.0);
    }
    const int steps = static_cast<int>(Distance(a, b) / 0.5);
    for (int i = 0; i < steps; ++i) {
      const Point2 q = a + (b - a) * (double(i) / steps);
      truth.emplace_back(q.x(), q.y(), heading);
    }
  }
  GraphSlamOptions o;
  o.first_pose = truth.front();
  o.loop_correction_per_metre = 0.05;  // a drift allowance wide enough to reach the block's corner
  GraphSlam slam(o);
  AddWithNoisyOdometry(slam, truth, rng, [&](const Pose2& pose) { return FrontScanFrom(map, pose, &rng); });
  ASSERT_GE(slam.loop_closures(), 1);
  for (const LoopClosure& c : slam.closures()) {
    const Pose2 diff = (truth[c.from_scan].inverse() * truth[c.to_scan]).inverse() * c.measurement;
    EXPECT_LT(std::hypot(diff.x, diff.y), 0.3) << c.from_scan << " -> " << c.to_scan;
  }
  EXPECT_LT(PositionRmse(slam.Trajectory(), truth), 0.1);
}

// A raw log of a robot weaving through an 8 m x 6 m room, one ODOM line every 0.2 s and a scan
// after every fourth, the scan stamped like the ODOM line before it. `lead` ODOM lines: how far
// ahead of that line the scan was really taken (0: at it; 1: at the line after it, as the public
// CARMEN logs' scans move).
std::string WeavingRoomLog(int lead) {
  const auto range = [](const Pose2& p, double a) {
    const double c = std::cos(p.theta + a), s = std::sin(p.theta + a);
    const double tx = c > 0 ? (8.0 - p.x) / c : c < 0 ? -p.x / c : 1e9;
    const double ty = s > 0 ? (6.0 - p.y) / s : s < 0 ? -p.y / s : 1e9;
    return std::min(tx, ty);
  };
  std::vector<Pose2> ticks{{2.0, 0.8, 0.0}};
  for (int k = 1; k < 160; ++k) {
    const double t = 0.2 * k, turn = 0.8 * std::sin(0.5 * t) * 0.2;
    const Pose2& b = ticks.back();
    ticks.push_back(b * Pose2(0.06, 0.0, turn));
  }
  std::ostringstream log;
  for (size_t k = 0; k + 1 < ticks.size(); ++k) {
    const Pose2& o = ticks[k];
    const double stamp = 100.0 + 0.2 * static_cast<double>(k);
    log << "ODOM " << o.x << " " << o.y << " " << o.theta << " 0 0 0 " << stamp << " h " << stamp << "\n";
    if (k % 4 != 3) continue;
    const Pose2& at = ticks[k + static_cast<size_t>(lead)];
    EXPECT_TRUE(at.x > 0.5 && at.x < 7.5 && at.y > 0.5 && at.y < 5.5) << "the path leaves the room";
    log << "FLASER 181";
    for (int i = 0; i <= 180; ++i) log << " " << range(at, (i - 90) * M_PI / 180);
    log << " " << at.x << " " << at.y << " " << at.theta << " " << at.x << " " << at.y << " " << at.theta << " "
        << stamp << " h " << stamp << "\n";
  }
  return log.str();
}

// The median per-step error (m + rad) of a log's odometry at its scans against its scans' poses.
double MedianStepError(const CarmenLog& log, const std::vector<Pose2>& odometry) {
  std::vector<double> errors;
  for (size_t k = 1; k < log.scans.size(); ++k) {
    const Pose2 d =
        (log.scans[k - 1].pose.inverse() * log.scans[k].pose).inverse() * (odometry[k - 1].inverse() * odometry[k]);
    errors.push_back(std::hypot(d.x, d.y) + std::abs(d.theta));
  }
  std::sort(errors.begin(), errors.end());
  return errors[errors.size() / 2];
}

// The scans tell which ODOM line they were taken at: a log whose scans move with the line after
// them is paired there, one whose scans move with the line before them keeps that, and either
// way the paired odometry steps as the scans do.
TEST(OdometryPairing, FollowsTheOdomLineTheScansMoveWith) {
  const CarmenLog ahead = ParseCarmenLog(WeavingRoomLog(1), "ahead");
  const OdometryPairingEstimate found = EstimateOdometryPairing(ahead);
  EXPECT_GE(found.pairs, 20);
  EXPECT_FALSE(found.pairing.by_stamp) << Summary(found);
  EXPECT_GE(found.pairing.position, 0.75) << Summary(found);
  const double paired = MedianStepError(ahead, OdometryAtScans(ahead, found.pairing));
  const double stamped = MedianStepError(ahead, OdometryAtScans(ahead));
  EXPECT_LT(paired, 0.02) << Summary(found);
  EXPECT_GT(stamped, 3 * paired) << paired;

  const CarmenLog at = ParseCarmenLog(WeavingRoomLog(0), "at");
  const OdometryPairingEstimate kept = EstimateOdometryPairing(at);
  EXPECT_TRUE(kept.pairing.by_stamp || kept.pairing.position <= 0.25) << Summary(kept);
  EXPECT_LT(MedianStepError(at, PairedOdometryAtScans(at)), 0.02);

  // A log without ODOM lines keeps its scans' own odometry fields, and nothing is matched.
  const CarmenLog fields = ParseCarmenLog("FLASER 1 1.0 9 9 1 5 6 0.5 11.5 h 11.5\n", "fields");
  EXPECT_EQ(EstimateOdometryPairing(fields).pairs, 0);
  EXPECT_NEAR(PairedOdometryAtScans(fields).at(0).x, 5.0, 1e-9);
}

// A square loop driven in 0.5 m steps, turning on the spot at its corners.
std::vector<Pose2> SquareLoop() {
  std::vector<Pose2> out;
  Pose2 pose;
  for (int side = 0; side < 4; ++side) {
    for (int k = 0; k < 8; ++k) {
      out.push_back(pose);
      pose = pose * Pose2(0.5, 0.0, 0.0);
    }
    pose = pose * Pose2(0.0, 0.0, M_PI / 2);
  }
  return out;
}

TEST(RelativePoseError, NeedsNoCommonFrame) {
  const std::vector<Pose2> truth = SquareLoop();
  const Pose2 elsewhere(12.0, -3.0, 2.0);
  std::vector<Pose2> estimate(truth.size());
  std::transform(truth.begin(), truth.end(), estimate.begin(), [&](const Pose2& p) { return elsewhere * p; });
  const RelativeError e = RelativePoseError(estimate, truth);
  EXPECT_EQ(e.relations, static_cast<int>(truth.size()) - 1);
  EXPECT_NEAR(e.translation_mean, 0.0, 1e-12);
  EXPECT_NEAR(e.rotation_rmse, 0.0, 1e-12);
  EXPECT_NEAR(AlignedTrajectoryError(estimate, truth).position_rmse, 0.0, 1e-9);
}

TEST(AlignedTrajectoryError, TellsAMapDrawnLargerFromOneBent) {
  const std::vector<Pose2> truth = SquareLoop();
  const Pose2 elsewhere(12.0, -3.0, 2.0);
  // The loop drawn 1 % larger, in another frame: the rigid fit counts it as error, the similarity
  // fit takes it out and reads the scale.
  std::vector<Pose2> larger(truth.size());
  std::transform(truth.begin(), truth.end(), larger.begin(),
                 [&](const Pose2& p) { return elsewhere * Pose2(1.01 * p.x, 1.01 * p.y, p.theta); });
  const TrajectoryError scaled = AlignedTrajectoryError(larger, truth);
  EXPECT_GT(scaled.position_rmse, 0.01);
  EXPECT_NEAR(scaled.scale, 1.01, 1e-9);
  EXPECT_NEAR(scaled.similarity_rmse, 0.0, 1e-9);
  // A bend is no scale: the similarity fit leaves most of it.
  std::vector<Pose2> bent = truth;
  for (size_t i = truth.size() / 2; i < truth.size(); ++i) bent[i] = Pose2(0.0, 0.0, 0.05) * truth[i];
  const TrajectoryError kinked = AlignedTrajectoryError(bent, truth);
  EXPECT_GT(kinked.similarity_rmse, 0.5 * kinked.position_rmse);
}

TEST(RelativePoseError, ABendCostsOneRelationWhereTheAbsoluteErrorCostsMostPoses) {
  const std::vector<Pose2> truth = SquareLoop();
  const int bend = 10;
  std::vector<Pose2> estimate = truth;
  // Everything after pose `bend` turned 0.05 rad about it and pushed 0.1 m on.
  const Pose2 kink(0.1, 0.0, 0.05);
  for (size_t i = bend + 1; i < estimate.size(); ++i)
    estimate[i] = truth[bend] * kink * (truth[bend].inverse() * truth[i]);
  const RelativeError e = RelativePoseError(estimate, truth);
  const double n = static_cast<double>(e.relations);
  // Only the step from `bend` to the next differs: by the kink itself, seen from the true step.
  const Pose2 step = truth[bend].inverse() * truth[bend + 1];
  const Pose2 wrong = step.inverse() * kink * step;
  EXPECT_NEAR(e.translation_mean, std::hypot(wrong.x, wrong.y) / n, 1e-12);
  EXPECT_NEAR(e.translation_rmse, std::hypot(wrong.x, wrong.y) / std::sqrt(n), 1e-12);
  EXPECT_NEAR(e.rotation_mean, 0.05 / n, 1e-12);
  // Two steps apart, the two relations spanning the bend differ, by the same kink.
  EXPECT_NEAR(RelativePoseError(estimate, truth, 2).rotation_mean, 2 * 0.05 / (n - 1), 1e-12);
  // After alignment, the bend leaves most poses of the loop more than 2 cm off.
  const Pose2 alignment = AlignedTrajectoryError(estimate, truth).alignment;
  int off = 0;
  for (size_t i = 0; i < truth.size(); ++i)
    off += Distance((alignment * estimate[i]).translation(), truth[i].translation()) > 0.02;
  EXPECT_GT(off, static_cast<int>(truth.size()) / 2);
}

// Odometry that reads every step 10 % long errs along the travel only, turns or not.
TEST(RelativePoseError, SplitsTheErrorAlongTheTravelAndAcrossIt) {
  const std::vector<Pose2> truth = SquareLoop();
  std::vector<Pose2> estimate{truth.front()};
  for (size_t i = 1; i < truth.size(); ++i) {
    const Pose2 step = truth[i - 1].inverse() * truth[i];
    estimate.push_back(estimate.back() * Pose2(1.1 * step.x, 1.1 * step.y, step.theta));
  }
  const RelativeError e = RelativePoseError(estimate, truth);
  EXPECT_NEAR(e.along_rmse, 0.05, 1e-12);  // every step is 0.5 m
  EXPECT_NEAR(e.across_rmse, 0.0, 1e-12);
  EXPECT_NEAR(e.translation_rmse, 0.05, 1e-12);
  EXPECT_NEAR(e.rotation_rmse, 0.0, 1e-12);
}

TEST(RelativePoseError, RefusesTrajectoriesItCannotCompare) {
  const std::vector<Pose2> truth = SquareLoop();
  const std::vector<Pose2> shorter(truth.begin(), truth.end() - 1);
  EXPECT_THROW(RelativePoseError(shorter, truth), Error);
  EXPECT_THROW(RelativePoseError(truth, truth, 0), Error);
  EXPECT_THROW(RelativePoseError(truth, truth, static_cast<int>(truth.size())), Error);
  EXPECT_THROW(RelativePoseError({Pose2()}, {Pose2()}), Error);
}

}  // namespace
}  // namespace navd::mapping
