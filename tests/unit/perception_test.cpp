// The depth camera's way into the costmap: navsim's camera, PCL's filter (floor,
// heights, speckle) and the voxel layer (marking, clearing, decay); the scenario's solids; the
// PointCloud2 layout both sides use.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <random>

#include "dds/point_cloud2.h"
#include "services/common/camera_frame.h"
#include "services/common/error.h"
#include "services/perception/depth_obstacle_layer.h"
#include "services/perception/obstacle_cloud_filter.h"
#include "services/perception/voxel_obstacle_layer.h"
#include "simulator/depth_camera.h"
#include "services/common/disc.h"
#include "simulator/scenario.h"
#include "simulator/simulation.h"

namespace navd {
namespace {

using perception::DepthObstacleLayer;
using perception::FilteredCloud;
using perception::ObstacleCloudFilter;
using perception::ObstacleCloudFilterOptions;
using sim::DepthCamera;
using sim::Solid;

// A 20 x 20 m hall with walls at its edges: from its middle they are beyond the camera's 5 m.
OccupancyGrid Room() {
  OccupancyGrid g(400, 400, 0.05, {-5.0, -5.0});
  g.FillBox({-5.0, -5.0}, {15.0, -4.9});
  g.FillBox({-5.0, 14.9}, {15.0, 15.0});
  g.FillBox({-5.0, -5.0}, {-4.9, 15.0});
  g.FillBox({14.9, -5.0}, {15.0, 15.0});
  return g;
}

DepthCameraDescription Camera() {
  DepthCameraDescription d;
  d.mount_x = 0.1;
  d.mount_z = 1.0;
  d.tilt = 25.0 * M_PI / 180.0;
  return d;
}

std::vector<Eigen::Vector3f> Capture(const DepthCameraDescription& d, const Pose2& robot,
                                     const std::vector<Solid>& solids, uint64_t seed = 1) {
  const RayCaster walls(Room());
  std::mt19937_64 rng(seed);
  return DepthCamera(d).Capture(robot, walls, solids, {}, -1, rng);
}

ObstacleCloudFilterOptions FilterFor(double robot_height) {
  return perception::DepthObstacleLayerOptions::ForRobot(robot_height).filter;
}

// A table 0.8 x 0.6 m, its top at 0.71-0.75 m, legs 5 cm square, as the scenario makes them.
std::vector<Solid> Table(double x0, double y0, double x1, double y1) {
  std::vector<Solid> t = {{{{x0, y0}, {x1, y1}}, 0.71, 0.75}};
  for (double x : {x0, x1 - 0.05})
    for (double y : {y0, y1 - 0.05}) t.push_back({{{x, y}, {x + 0.05, y + 0.05}}, 0.0, 0.71});
  return t;
}

TEST(DepthCamera, SeesTheFloorWhereItsTiltPutsIt) {
  DepthCameraDescription d = Camera();
  d.noise = 0.0;
  d.holes = 0.0;
  const auto points = Capture(d, {5.0, 5.0, 0.0}, {});
  // The upper rows look near level: the floor there is beyond range_max.
  ASSERT_GT(points.size(), 0.6 * d.width * d.height);
  // The pixel nearest the optical axis meets the floor at mount_z / sin(tilt) along it.
  const Eigen::Vector3f* centre = &points.front();
  for (const auto& p : points)
    if (std::hypot(p.x() / p.z(), p.y() / p.z()) < std::hypot(centre->x() / centre->z(), centre->y() / centre->z()))
      centre = &p;
  EXPECT_NEAR(centre->z(), 1.0 / std::sin(d.tilt), 0.03);
  // Every point on the floor, in the robot frame.
  const Eigen::Isometry3f to_robot = RobotFromOptical(d);
  for (const auto& p : points) EXPECT_NEAR((to_robot * p).z(), 0.0, 1e-3);
  // Noise grows with depth squared and some pixels read nothing.
  d.noise = 0.002;
  d.holes = 0.05;
  const auto noisy = Capture(d, {5.0, 5.0, 0.0}, {});
  EXPECT_LT(noisy.size(), 0.97 * points.size());
  EXPECT_GT(noisy.size(), 0.9 * points.size());
}

// The depth pixel (u, v) reads, ray-cast exactly on its own: the floor, the walls by a 2-D cast
// along its own bearing, the solids by a slab test and the bodies as upright cylinders; NaN when
// nothing is within the camera's range.
double ReferenceDepth(const DepthCameraDescription& d, const Pose2& robot, const RayCaster& walls,
                      const std::vector<Solid>& solids, const std::vector<Disc>& bodies, int u, int v) {
  const auto [fx, fy, cx, cy] = IntrinsicsOf(d);
  const Eigen::Vector3d optical((u + 0.5 - cx) / fx, (v + 0.5 - cy) / fy, 1.0);
  const Eigen::Vector3d in_robot = RobotFromOptical(d).linear().cast<double>() * optical;
  const Eigen::Vector3d ray(std::cos(robot.theta) * in_robot.x() - std::sin(robot.theta) * in_robot.y(),
                            std::sin(robot.theta) * in_robot.x() + std::cos(robot.theta) * in_robot.y(), in_robot.z());
  const Point2 origin = robot * Point2(d.mount_x, d.mount_y);
  const Eigen::Vector3d camera(origin.x(), origin.y(), d.mount_z);
  const double across = std::hypot(ray.x(), ray.y());
  double depth = ray.z() < 0.0 ? d.mount_z / -ray.z() : INFINITY;
  const double wall = walls.CastOpenEdge(origin, std::atan2(ray.y(), ray.x()), 20.0);
  if (wall < 20.0) depth = std::min(depth, wall / across);
  for (const Solid& solid : solids) {
    const Eigen::Vector3d lo = Eigen::Vector3d(solid.box.min.x(), solid.box.min.y(), solid.z_min) - camera;
    const Eigen::Vector3d hi = Eigen::Vector3d(solid.box.max.x(), solid.box.max.y(), solid.z_max) - camera;
    double enter = 0.0, leave = INFINITY;
    for (int k = 0; k < 3; ++k) {
      if (ray[k] == 0.0) {
        if (lo[k] > 0.0 || hi[k] < 0.0) leave = -1.0;
        continue;
      }
      const double a = lo[k] / ray[k], b = hi[k] / ray[k];
      enter = std::max(enter, std::min(a, b));
      leave = std::min(leave, std::max(a, b));
    }
    if (enter <= leave && enter > 0.0) depth = std::min(depth, enter);
  }
  for (const Disc& body : bodies) {
    const double along = RayDiscDistance(origin, Point2(ray.x(), ray.y()) / across, body) / across;
    const double z = d.mount_z + along * ray.z();
    if (std::isfinite(along) && z >= 0.0 && z <= DepthCamera::kBodyHeight) depth = std::min(depth, along);
  }
  return depth >= d.range_min && depth <= d.range_max ? depth : NAN;
}

TEST(DepthCamera, ReadsWhatAPerPixelRayCastOfTheSceneReads) {
  // Walls near enough to see, at an angle, with a doorway and a pillar; a table the camera is
  // partly beside and behind, a low box, a person; the camera turned to see them from several places.
  OccupancyGrid g = Room();
  g.FillBox({7.0, 2.0}, {7.1, 4.6});  // a wall with a doorway from 4.6 to 5.4 m
  g.FillBox({7.0, 5.4}, {7.1, 8.0});
  g.FillBox({8.5, 4.9}, {8.6, 5.0});  // a pillar seen through the doorway
  for (int k = 0; k < 40; ++k) g.FillBox({4.0 + 0.05 * k, 7.0 + 0.025 * k}, {4.05 + 0.05 * k, 7.05 + 0.025 * k});
  const RayCaster walls(g);
  std::vector<Solid> solids = Table(5.1, 4.3, 5.9, 4.9);
  solids.push_back({{{6.0, 5.6}, {6.3, 5.9}}, 0.0, 0.15});  // under a laser's plane
  const std::vector<Disc> bodies = {{{6.2, 4.2}, 0.25, 7}};
  DepthCameraDescription d = Camera();
  d.noise = 0.0;
  d.holes = 0.0;
  const DepthCamera camera(d);
  const auto [fx, fy, cx, cy] = IntrinsicsOf(d);
  int checked = 0, agree = 0, only_one = 0, on_solids_or_bodies = 0;
  for (const Pose2 robot : {Pose2{5.0, 5.0, 0.0}, Pose2{5.3, 4.0, 1.2}, Pose2{4.6, 5.0, -0.4}, Pose2{6.0, 6.5, -1.8}}) {
    std::mt19937_64 rng(1);
    const auto points = camera.Capture(robot, walls, solids, bodies, -1, rng);
    std::vector<double> image(static_cast<size_t>(d.width) * d.height, NAN);
    for (const Eigen::Vector3f& p : points) {
      const int u = static_cast<int>(std::floor(fx * p.x() / p.z() + cx));
      const int v = static_cast<int>(std::floor(fy * p.y() / p.z() + cy));
      ASSERT_TRUE(u >= 0 && v >= 0 && u < d.width && v < d.height);
      image[static_cast<size_t>(v) * d.width + u] = p.z();
    }
    for (int v = 0; v < d.height; ++v) {
      for (int u = 0; u < d.width; ++u) {
        const double want = ReferenceDepth(d, robot, walls, solids, bodies, u, v);
        const double got = image[static_cast<size_t>(v) * d.width + u];
        if (std::isnan(want) != std::isnan(got)) ++only_one;
        if (std::isnan(want) || std::isnan(got)) continue;
        ++checked;
        agree += std::abs(want - got) <= 0.01 + 0.01 * want;
        on_solids_or_bodies += want < ReferenceDepth(d, robot, walls, {}, {}, u, v) - 0.05;
      }
    }
  }
  // Pixel-wide wall casts, some of them the mean of their neighbours, miss by more only at a
  // wall's edges, where the depth jumps: a few pixels in a thousand.
  EXPECT_GT(checked, 60000);
  EXPECT_GT(on_solids_or_bodies, 3000);
  EXPECT_GT(agree, 0.997 * checked) << agree << " of " << checked;
  EXPECT_LT(only_one, 0.002 * checked);
}

TEST(ObstacleCloudFilter, RemovesTheFloorOfATiltedCamera) {
  const DepthCameraDescription d = Camera();
  const ObstacleCloudFilter filter(FilterFor(1.1), d);
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    const FilteredCloud f = filter.Filter(Capture(d, {5.0, 5.0, 0.7 * seed}, {}, seed));
    EXPECT_TRUE(f.floor_fitted);
    EXPECT_NEAR(f.floor_plane.w(), 0.0, 0.02);
    EXPECT_GT(f.floor_plane.z(), 0.99);
    EXPECT_GT(f.floor.size(), 100u);
    EXPECT_TRUE(f.obstacles.empty()) << f.obstacles.size() << " floor points taken for obstacles (seed " << seed << ")";
  }
  // A floor that is not level in the camera's frame (a camera mounted 3 degrees off): the plane is fitted where it is.
  DepthCameraDescription off = d;
  off.tilt += 3.0 * M_PI / 180.0;
  const FilteredCloud f = ObstacleCloudFilter(FilterFor(1.1), d).Filter(Capture(off, {5.0, 5.0, 0.0}, {}));
  EXPECT_TRUE(f.floor_fitted);
  EXPECT_TRUE(f.obstacles.empty()) << f.obstacles.size();
}

TEST(ObstacleCloudFilter, KeepsATableTopAtItsHeightAndALowBox) {
  const DepthCameraDescription d = Camera();
  std::vector<Solid> solids = Table(6.2, 4.6, 7.0, 5.4);
  solids.push_back({{{6.0, 3.6}, {6.3, 3.9}}, 0.0, 0.15});  // a box lower than a laser at 0.3 m
  const FilteredCloud f = ObstacleCloudFilter(FilterFor(1.1), d).Filter(Capture(d, {5.0, 5.0, 0.0}, solids));
  int top = 0, box = 0;
  for (const Eigen::Vector3f& p : f.obstacles) {
    const Point2 at = Pose2{5.0, 5.0, 0.0} * Point2(p.x(), p.y());
    if (at.x() > 6.15 && at.x() < 7.05 && at.y() > 4.55 && at.y() < 5.45 && p.z() > 0.68) {
      ++top;
      EXPECT_NEAR(p.z(), 0.73, 0.06);
    }
    if (at.x() > 5.95 && at.x() < 6.35 && at.y() > 3.55 && at.y() < 3.95) {
      ++box;
      EXPECT_LT(p.z(), 0.2);
    }
  }
  EXPECT_GT(top, 20);
  EXPECT_GT(box, 3);
  // A robot 0.6 m tall passes under the top: it is no obstacle to it.
  const FilteredCloud low = ObstacleCloudFilter(FilterFor(0.6), d).Filter(Capture(d, {5.0, 5.0, 0.0}, solids));
  for (const Eigen::Vector3f& p : low.obstacles) EXPECT_LT(p.z(), 0.66);
}

TEST(ObstacleCloudFilter, DropsSpeckle) {
  const DepthCameraDescription d = Camera();
  std::vector<Eigen::Vector3f> points = Capture(d, {5.0, 5.0, 0.0}, {});
  // Lone returns in the air (dust, a stereo mismatch), each far from any other.
  const Eigen::Isometry3f to_optical = RobotFromOptical(d).inverse();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> ahead(1.0f, 4.0f), side(-1.0f, 1.0f), up(0.3f, 1.0f);
  for (int i = 0; i < 40; ++i) points.push_back(to_optical * Eigen::Vector3f(ahead(rng), side(rng), up(rng)));
  const FilteredCloud f = ObstacleCloudFilter(FilterFor(1.1), d).Filter(points);
  EXPECT_TRUE(f.obstacles.empty()) << f.obstacles.size() << " speckle points kept";
  ObstacleCloudFilterOptions keep = FilterFor(1.1);
  keep.speckle_neighbours = 0;
  EXPECT_GT(ObstacleCloudFilter(keep, d).Filter(points).obstacles.size(), 30u);  // the step that removes them
}

class DepthObstacleLayerAt : public ::testing::TestWithParam<std::pair<int, int>> {};

// At the default 212 x 120, whose every pixel the filter reads, and at 640 x 480, read every
// third row and column.
TEST_P(DepthObstacleLayerAt, MarksABoxAndClearsItWhenItIsMovedAway) {
  DepthCameraDescription d = Camera();
  d.width = GetParam().first;
  d.height = GetParam().second;
  const auto options = perception::DepthObstacleLayerOptions::ForRobot(1.1);
  DepthObstacleLayer layer(d, options);
  layer.SetMap(Room());
  const Pose2 robot{5.0, 5.0, 0.0};
  const std::vector<Solid> box = {{{{6.5, 4.8}, {6.9, 5.2}}, 0.0, 0.2}};
  auto marked_in = [&](double x0, double y0, double x1, double y1) {
    int n = 0;
    for (const Point2& p : *layer.Obstacles()) n += p.x() > x0 && p.x() < x1 && p.y() > y0 && p.y() < y1;
    return n;
  };
  layer.AddCloud(Capture(d, robot, box, 1), robot, 0.0);
  EXPECT_GT(marked_in(6.4, 4.7, 7.0, 5.3), 3);
  EXPECT_EQ(marked_in(0.0, 0.0, 6.4, 10.0), 0) << "marks off the box";
  // The box taken away: the camera sees the floor where it stood, and that clears it (two frames,
  // 67 ms apart: a pixel may be a hole in one).
  layer.AddCloud(Capture(d, robot, {}, 2), robot, 0.1);
  layer.AddCloud(Capture(d, robot, {}, 6), robot, 0.167);
  EXPECT_EQ(marked_in(6.4, 4.7, 7.0, 5.3), 0);
  // Put back, then out of view: the mark stays until it decays.
  layer.AddCloud(Capture(d, robot, box, 3), robot, 0.2);
  const Pose2 away{5.0, 5.0, M_PI};
  layer.AddCloud(Capture(d, away, box, 4), away, 1.0);
  EXPECT_GT(marked_in(6.4, 4.7, 7.0, 5.3), 3);
  layer.AddCloud(Capture(d, away, box, 5), away, 1.0 + options.layer.decay + 1.0);
  EXPECT_EQ(marked_in(6.4, 4.7, 7.0, 5.3), 0);
}
INSTANTIATE_TEST_SUITE_P(Resolutions, DepthObstacleLayerAt,
                         ::testing::Values(std::make_pair(212, 120), std::make_pair(640, 480)));

// Marks whose pixels see past them are cleared, the table top that is seen again stays, and a mark
// outside the view is left alone.
TEST(VoxelObstacleLayer, ClearsWhatTheCameraSawPastAndNothingElse) {
  const DepthCameraDescription d = Camera();
  perception::VoxelObstacleLayer layer(Room());
  auto view_of = [&](const std::vector<Solid>& solids, const Pose2& robot = {5.0, 5.0, 0.0}) {
    Eigen::Isometry3d map_from_robot = Eigen::Isometry3d::Identity();
    map_from_robot.translation() = Eigen::Vector3d(robot.x, robot.y, 0.0);
    perception::DepthView v = perception::DepthView::Of(Capture(d, robot, solids), IntrinsicsOf(d), d.width, d.height);
    v.map_from_optical = map_from_robot * RobotFromOptical(d).cast<double>();
    v.range_min = d.range_min;
    v.range_max = d.range_max;
    v.noise = d.noise;
    return v;
  };
  const std::vector<Solid> table = Table(6.6, 4.6, 7.4, 5.4);
  const CellIndex top = Room().CellOf({7.0, 5.0}), behind = Room().CellOf({8.0, 6.2}),
                  aside = Room().CellOf({5.0, 8.0});
  layer.Update(view_of(table), {{7.0, 5.0, 0.73}, {8.0, 6.2, 0.3}, {5.0, 8.0, 0.3}}, 0.0);
  EXPECT_EQ(layer.obstacle_count(), 3u);
  layer.Update(view_of(table), {{7.0, 5.0, 0.73}}, 0.1);
  EXPECT_TRUE(layer.IsObstacle(top));
  EXPECT_FALSE(layer.IsObstacle(behind));  // nothing there: the camera saw the floor past it
  EXPECT_TRUE(layer.IsObstacle(aside));    // out of view
  // The table taken away: from where the pixels through its top see the floor within range.
  layer.Update(view_of({}, {6.0, 5.0, 0.0}), {}, 0.2);
  EXPECT_FALSE(layer.IsObstacle(top));
  EXPECT_EQ(layer.obstacle_count(), 1u);
}

TEST(Scenarios, SolidsHaveHeightsTheLaserAndTheRobotMeetOrNot) {
  const std::string world =
      "name: room\nmap: {resolution: 0.05, size: [6, 4], boxes: [[0, 0, 6, 0.1], [0, 3.9, 6, 4], [0, 0, 0.1, 4], "
      "[5.9, 0, 6, 4]]}\nrobot: {start: [1, 2, 0], height: 1.1}\nlaser: {height: 0.3}\ncamera: {tilt_deg: 20}\n";
  const std::string path = ::testing::TempDir() + "/room3d.yaml";
  { std::ofstream(path) << world; }
  const sim::Scenario s = sim::ParseScenario("world: " + path +
                                                 "\nhidden_obstacles:\n  solids:\n"
                                                 "    - {type: table, box: [2.0, 1.6, 2.8, 2.4], height: 0.75}\n"
                                                 "    - {type: box, box: [4.0, 1.0, 4.3, 1.3], height: 0.15}\n"
                                                 "    - {type: shelf, box: [4.0, 3.4, 5.0, 3.9], z: [0.5, 1.8]}\n"
                                                 "    - {type: solid, box: [3.0, 0.1, 3.5, 0.5], z: [1.5, 2.0]}\n",
                                             "s.yaml", ".");
  EXPECT_EQ(s.hidden_obstacles, 4);
  ASSERT_TRUE(s.robots[0].camera);
  EXPECT_NEAR(s.robots[0].camera->tilt, 20.0 * M_PI / 180.0, 1e-9);
  sim::Simulation simulation(s, {});
  // The table: the laser sees its legs, not its top; the robot (1.1 m) meets both.
  EXPECT_TRUE(simulation.laser_truth().DiscHitsWall({2.025, 1.625}, 0.01));
  EXPECT_FALSE(simulation.laser_truth().DiscHitsWall({2.4, 2.0}, 0.01));
  EXPECT_TRUE(simulation.truth().DiscHitsWall({2.4, 2.0}, 0.01));
  // The low box and the overhanging shelf: below and above the laser's plane, in the robot's way.
  EXPECT_FALSE(simulation.laser_truth().DiscHitsWall({4.15, 1.15}, 0.01));
  EXPECT_TRUE(simulation.truth().DiscHitsWall({4.15, 1.15}, 0.01));
  EXPECT_FALSE(simulation.laser_truth().DiscHitsWall({4.5, 3.6}, 0.01));
  EXPECT_TRUE(simulation.truth().DiscHitsWall({4.5, 3.6}, 0.01));
  // Above the robot's top: it drives under it.
  EXPECT_FALSE(simulation.truth().DiscHitsWall({3.25, 0.3}, 0.01));
  // The camera's walls are the truth without the solids.
  EXPECT_FALSE(simulation.camera_walls().DiscHitsWall({2.4, 2.0}, 0.01));
  EXPECT_TRUE(simulation.camera_walls().DiscHitsWall({0.05, 2.0}, 0.01));
  // Bad solids name the field.
  for (const auto& [text, field] : std::vector<std::pair<std::string, std::string>>{
           {"{type: table, box: [2, 1, 3, 2]}", "solids[0]"},
           {"{type: shelf, box: [2, 1, 3, 2], z: [1.0, 0.5]}", "solids[0].z"},
           {"{type: chair, box: [2, 1, 3, 2], height: 1}", "solids[0].type"},
           {"{type: box, box: [40, 40, 41, 41], height: 1}", "solids[0].box"}}) {
    try {
      sim::ParseScenario("world: " + path + "\nhidden_obstacles: {solids: [" + text + "]}\n", "s.yaml", ".");
      ADD_FAILURE() << text << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
}

// Bad world files are refused with the field named: a camera too large for the simulator to
// render, a filter option out of range, and a world whose map is itself (followed four files deep,
// then refused).
TEST(Worlds, BadCamerasAndWorldsThatNameThemselvesAreRefused) {
  const std::string dir = ::testing::TempDir();
  auto refused = [&](const std::string& name, const std::string& text, const std::string& what) {
    const std::string path = dir + "/" + name;
    { std::ofstream(path) << text; }
    try {
      LoadWorldFile(path);
      ADD_FAILURE() << name << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  const std::string map = "map: {resolution: 0.05, size: [4, 4]}\nrobot: {start: [2, 2, 0]}\n";
  refused("big.yaml", map + "camera: {resolution: [4096, 4096]}\n", "camera.resolution");
  refused("tilt.yaml", map + "camera: {tilt_deg: 95}\n", "camera.tilt_deg");
  refused("self.yaml", "map: self.yaml\nrobot: {start: [2, 2, 0]}\n", "more than 4 world files");
  perception::ObstacleCloudFilterOptions bad;
  bad.floor_sample = 0;
  EXPECT_THROW(ObstacleCloudFilter(bad, Camera()), Error);
}

TEST(PointCloud2, RoundTripsAndReadsOtherLayouts) {
  const std::vector<Eigen::Vector3f> points = {{1.0f, 2.0f, 3.0f}, {-0.5f, 0.25f, 4.5f}};
  auto m = dds::EncodeXyzCloud(points, 12.5, "camera_depth_optical_frame");
  EXPECT_EQ(m.header().frame_id(), "camera_depth_optical_frame");
  ASSERT_EQ(m.fields().size(), 3u);
  EXPECT_EQ(m.fields()[2].name(), "z");
  EXPECT_EQ(m.fields()[2].offset(), 8u);
  EXPECT_EQ(m.fields()[2].datatype(), dds::kFloat32);
  EXPECT_EQ(m.point_step(), 12u);
  EXPECT_EQ(m.row_step(), 24u);
  EXPECT_EQ(dds::DecodeXyzCloud(m), points);

  // An organized, big-endian cloud of 16-byte FLOAT64 points with an intensity field first and a
  // NaN pixel, as other drivers send: the rules find x, y, z by name.
  sensor_msgs::msg::dds_::PointCloud2_ o;
  o.height(2);
  o.width(1);
  o.point_step(32);
  o.row_step(32);
  o.is_bigendian(true);
  const char* names[] = {"intensity", "x", "y", "z"};
  for (uint32_t k = 0; k < 4; ++k) {
    sensor_msgs::msg::dds_::PointField_ f;
    f.name(names[k]);
    f.offset(k == 0 ? 0 : 8 * k);
    f.datatype(k == 0 ? dds::kFloat32 : dds::kFloat64);
    f.count(1);
    o.fields().push_back(f);
  }
  o.data().resize(64, 0);
  auto put = [&](size_t at, double v) {
    uint8_t b[8];
    std::memcpy(b, &v, 8);
    for (int i = 0; i < 8; ++i) o.data()[at + i] = b[7 - i];  // host is little-endian
  };
  put(8, 1.5);
  put(16, -2.0);
  put(24, 3.25);
  put(32 + 8, std::nan(""));
  const auto read = dds::DecodeXyzCloud(o);
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(read[0], Eigen::Vector3f(1.5f, -2.0f, 3.25f));

  // Layouts the rules refuse, each named.
  auto refused = [](const sensor_msgs::msg::dds_::PointCloud2_& bad, const std::string& what) {
    try {
      dds::DecodeXyzCloud(bad);
      ADD_FAILURE() << what << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  auto no_z = m;
  no_z.fields().pop_back();
  refused(no_z, "no 'z' field");
  auto short_data = m;
  short_data.data().resize(20);
  refused(short_data, "data holds 20 bytes");
  auto integer = m;
  integer.fields()[0].datatype(dds::kInt16);
  refused(integer, "fields[0] (x).datatype");
  auto outside = m;
  outside.fields()[1].offset(10);
  refused(outside, "fields[1] (y).offset");
  auto short_rows = m;
  short_rows.row_step(12);
  refused(short_rows, "row_step 12 is under width * point_step (24)");
}

}  // namespace
}  // namespace navd
