// map_server YAML + PGM reading, PNG export, world files, and the embedded default world.
#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <zlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "services/common/error.h"
#include "services/common/map_server_format.h"
#include "services/common/png_format.h"
#include "services/common/text_file.h"
#include "services/common/tum_trajectory.h"
#include "services/common/world.h"
#include "services/planning/costmap.h"
#include "services/planning/grid_astar_planner.h"
#include "services/planning/planning_engine.h"
#include "tests/support/process.h"

namespace navd {
namespace {

std::string Write(const std::string& dir, const std::string& name, const std::string& contents) {
  std::string path = dir + "/" + name;
  std::ofstream(path, std::ios::binary) << contents;
  return path;
}

std::pair<ErrorCode, std::string> ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return {e.code(), e.what()};
  }
  return {ErrorCode::kInternal, "no error"};
}

TEST(MapServerFormat, DecodesBinaryPgmWithThresholdsAndFlip) {
  // 3x2 image, top row first: black, white, mid-grey / white, white, black.
  std::string pgm = "P5\n# comment\n3 2\n255\n";
  pgm += std::string{'\x00', '\xff', '\x80', '\xff', '\xff', '\x00'};
  MapServerParams p;
  p.resolution = 0.5;
  p.origin = {-1.0, 2.0};
  const OccupancyGrid g = DecodeMapServerImage(pgm, p, "t.pgm");
  EXPECT_EQ(g.width(), 3);
  EXPECT_EQ(g.height(), 2);
  EXPECT_EQ(g.at({0, 1}), OccupancyGrid::kOccupied);  // top-left pixel is the upper row
  EXPECT_EQ(g.at({1, 1}), OccupancyGrid::kFree);
  EXPECT_EQ(g.at({2, 1}), OccupancyGrid::kUnknown);  // occupancy 0.5: between thresholds
  EXPECT_EQ(g.at({2, 0}), OccupancyGrid::kOccupied);
  EXPECT_EQ(g.CellOf({-0.9, 2.1}), (CellIndex{0, 0}));
}

TEST(MapServerFormat, NegateAndAsciiPgm) {
  MapServerParams p;
  p.negate = true;
  const OccupancyGrid g = DecodeMapServerImage("P2 2 1 255 0 255", p, "t.pgm");
  EXPECT_EQ(g.at({0, 0}), OccupancyGrid::kFree);
  EXPECT_EQ(g.at({1, 0}), OccupancyGrid::kOccupied);
}

TEST(MapServerFormat, LoadsYamlWithRelativeImage) {
  const std::string dir = testing::MakeTempDir();
  Write(dir, "m.pgm", std::string("P5 2 2 255\n") + std::string{'\x00', '\xff', '\xff', '\xff'});
  const std::string yaml = Write(dir, "m.yaml", "image: m.pgm\nresolution: 0.1\norigin: [1.0, 2.0, 0.0]\n");
  const OccupancyGrid g = LoadMapServerMap(yaml);
  EXPECT_EQ(g.width(), 2);
  EXPECT_DOUBLE_EQ(g.resolution(), 0.1);
  EXPECT_EQ(g.at({0, 1}), OccupancyGrid::kOccupied);
}

// A 6 x 4 m room at 0.1 m: a wall all round and a 1.2 m pillar over the centre.
std::string RoomPgm() {
  std::string pixels;
  for (int row = 0; row < 40; ++row) {
    for (int col = 0; col < 60; ++col) {
      const bool wall = row == 0 || col == 0 || row == 39 || col == 59;
      const bool pillar = std::abs(col - 29.5) < 6 && std::abs(row - 19.5) < 6;
      pixels += (wall || pillar) ? '\x00' : '\xff';
    }
  }
  return "P5 60 40 255\n" + pixels;
}

TEST(WorldOrMapFile, BareMapsGetTheDefaultRobotAtTheFreeSpotNearestTheCentre) {
  const std::string dir = testing::MakeTempDir();
  Write(dir, "room.pgm", RoomPgm());
  const std::string yaml = Write(dir, "room.yaml", "image: room.pgm\nresolution: 0.1\norigin: [0.0, 0.0, 0.0]\n");
  const World room = LoadWorldOrMapFile(yaml);
  EXPECT_EQ(room.name, "room");
  EXPECT_EQ(room.map.width(), 60);
  EXPECT_DOUBLE_EQ(room.robot.radius, RobotDescription{}.radius);
  // Next to the pillar (x, y in [2.4, 3.6] x [1.4, 2.6]), as near the centre (3, 2) as fits.
  EXPECT_FALSE(room.map.DiscHitsObstacle(room.start.translation(), room.robot.radius + 0.04));
  EXPECT_LT((room.start.translation() - Point2(3, 2)).norm(), 0.6 + room.robot.radius + 0.15);

  const World arena = LoadWorldOrMapFile(std::string(NAVD_SOURCE_DIR) + "/tests/data/movingai/arena.map");
  EXPECT_EQ(arena.name, "arena");
  EXPECT_FALSE(arena.map.DiscHitsObstacle(arena.start.translation(), arena.robot.radius));

  const World world = LoadWorldOrMapFile(std::string(NAVD_SOURCE_DIR) + "/worlds/warehouse.yaml");
  EXPECT_EQ(world.start.translation(), DefaultWorld().start.translation());

  Write(dir, "solid.pgm", std::string("P5 3 3 255\n") + std::string(9, '\x00'));
  const std::string solid = Write(dir, "solid.yaml", "image: solid.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n");
  auto [code, msg] = ErrorOf([&] { LoadWorldOrMapFile(solid); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("solid.yaml: no free spot"), std::string::npos) << msg;
}

TEST(MapServerFormat, BadFilesNameTheProblem) {
  const std::string dir = testing::MakeTempDir();
  auto [code, msg] = ErrorOf([&] { LoadMapServerMap(dir + "/missing.yaml"); });
  EXPECT_EQ(code, ErrorCode::kNotFound);
  EXPECT_NE(msg.find("missing.yaml"), std::string::npos);

  const std::string no_res = Write(dir, "a.yaml", "image: m.pgm\norigin: [0, 0, 0]\n");
  std::tie(code, msg) = ErrorOf([&] { LoadMapServerMap(no_res); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("resolution"), std::string::npos) << msg;

  const std::string malformed = Write(dir, "b.yaml", "image: [unclosed\n");
  std::tie(code, msg) = ErrorOf([&] { LoadMapServerMap(malformed); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("malformed YAML"), std::string::npos) << msg;

  Write(dir, "bad.pgm", "this is not an image");
  const std::string bad_image = Write(dir, "c.yaml", "image: bad.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  std::tie(code, msg) = ErrorOf([&] { LoadMapServerMap(bad_image); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("not a PGM"), std::string::npos) << msg;

  Write(dir, "short.pgm", "P5 10 10 255\nabc");
  const std::string truncated = Write(dir, "d.yaml", "image: short.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  std::tie(code, msg) = ErrorOf([&] { LoadMapServerMap(truncated); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;

  Write(dir, "garbage.pgm", "P2 2 1 255 12 x7");
  const std::string garbage = Write(dir, "f.yaml", "image: garbage.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  std::tie(code, msg) = ErrorOf([&] { LoadMapServerMap(garbage); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("pixel 'x7'"), std::string::npos) << msg;

  Write(dir, "bright.pgm", "P2 2 1 100 12 200");
  const std::string bright = Write(dir, "g.yaml", "image: bright.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  std::tie(code, msg) = ErrorOf([&] { LoadMapServerMap(bright); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("exceeds maxval"), std::string::npos) << msg;

  Write(dir, "ok.pgm", "P2 1 1 255 0");
  const std::string thresh =
      Write(dir, "h.yaml", "image: ok.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nfree_thresh: 0.9\n");
  std::tie(code, msg) = ErrorOf([&] { LoadMapServerMap(thresh); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("free_thresh"), std::string::npos) << msg;

  const std::string no_image = Write(dir, "e.yaml", "image: nowhere.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  std::tie(code, msg) = ErrorOf([&] { LoadMapServerMap(no_image); });
  EXPECT_EQ(code, ErrorCode::kNotFound);
  EXPECT_NE(msg.find("nowhere.pgm"), std::string::npos) << msg;
}

TEST(World, DefaultWarehouseParsesAndItsGoalsAreReachable) {
  const World w = DefaultWorld();
  EXPECT_EQ(w.name, "warehouse");
  EXPECT_EQ(w.map.width(), 200);
  EXPECT_NEAR(w.map.size_x(), 10.0, 1e-9);
  EXPECT_EQ(w.laser.beams, 683);
  EXPECT_NEAR(w.laser.fov, 240 * M_PI / 180, 1e-9);
  EXPECT_NEAR(w.robot.radius, 0.20, 1e-12);
  ASSERT_EQ(w.goals.size(), 3u);
  // The elevator shaft is solid.
  EXPECT_TRUE(w.map.IsOccupied(w.map.CellOf({8.5, 1.5})));
  MapStore maps;
  maps.Set(w.map, w.name);
  planning::PlanningEngine engine(maps, {.costmap = {w.robot.radius + 0.1, true},
                                         .default_planner = "astar",
                                         .start_recovery_radius = 0.5,
                                         .velocity = {}});
  engine.Register(std::make_unique<planning::GridAStarPlanner>());
  Point2 from = w.start.translation();
  for (const auto& g : w.goals) {
    EXPECT_NO_THROW(engine.ComputePath(from, g.translation(), "", {})) << FormatPoint(g.translation());
    from = g.translation();
  }
}

TEST(World, BadWorldFilesNameTheField) {
  const std::string dir = testing::MakeTempDir();
  auto [code, msg] = ErrorOf([&] { LoadWorldFile(dir + "/none.yaml"); });
  EXPECT_EQ(code, ErrorCode::kNotFound);
  EXPECT_NE(msg.find("world file"), std::string::npos) << msg;

  std::tie(code, msg) = ErrorOf([&] { LoadWorldFile(Write(dir, "a.yaml", "name: x\n")); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("'map'"), std::string::npos) << msg;

  std::tie(code, msg) =
      ErrorOf([&] { LoadWorldFile(Write(dir, "b.yaml", "map: {size: [5, 5]}\nrobot: {radius: -1}\n")); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("robot.radius"), std::string::npos) << msg;

  std::tie(code, msg) =
      ErrorOf([&] { LoadWorldFile(Write(dir, "c.yaml", "map: {size: [5, 5], boxes: [[1, 2, 3]]}\n")); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("map.boxes[0]"), std::string::npos) << msg;

  std::tie(code, msg) =
      ErrorOf([&] { LoadWorldFile(Write(dir, "d.yaml", "map: {size: [5, 5]}\nrobot: {start: [9, 9]}\n")); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("robot.start"), std::string::npos) << msg;

  std::tie(code, msg) = ErrorOf([&] { LoadWorldFile(Write(dir, "e.yaml", "map: {size: [5, 5]\n")); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("malformed YAML"), std::string::npos) << msg;

  std::tie(code, msg) = ErrorOf([&] { LoadWorldFile(Write(dir, "f.yaml", "map: {size: [5, .nan]}\n")); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("map.size[1]"), std::string::npos) << msg;

  std::tie(code, msg) =
      ErrorOf([&] { LoadWorldFile(Write(dir, "k.yaml", "map: {size: [5, 5]}\nrobot: {radious: 0.3}\n")); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("robot.radious"), std::string::npos) << msg;
  EXPECT_NE(msg.find("radius"), std::string::npos) << msg;  // says what is allowed

  std::tie(code, msg) =
      ErrorOf([&] { LoadWorldFile(Write(dir, "l.yaml", "map: {size: [5, 5]}\nsonar: {count: 16}\n")); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("'sonar'"), std::string::npos) << msg;

  // Sides whose cell counts multiply past 2^63 (found by the world fuzzer) are refused, not overflowed.
  std::tie(code, msg) = ErrorOf([&] { LoadWorldFile(Write(dir, "m.yaml", "map: {size: [8.9e16, 20]}\n")); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("map.size"), std::string::npos) << msg;

  std::tie(code, msg) = ErrorOf([&] { LoadWorldFile(Write(dir, "g.yaml", "map: {size: [0.01, 5]}\n")); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("map.size"), std::string::npos) << msg;

  std::tie(code, msg) = ErrorOf([&] {
    LoadWorldFile(Write(dir, "h.yaml", "map: {size: [5, 5]}\nrobot: {start: [1, 1], encoder_ticks_per_rev: 0.5}\n"));
  });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("robot.encoder_ticks_per_rev"), std::string::npos) << msg;

  std::tie(code, msg) =
      ErrorOf([&] { LoadWorldFile(Write(dir, "i.yaml", "map: {size: [5, 5]}\nlaser: {beams: 1e12}\n")); });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("laser.beams"), std::string::npos) << msg;

  std::tie(code, msg) = ErrorOf([&] {
    LoadWorldFile(Write(dir, "j.yaml", "map: {size: [5, 5], boxes: [[2, 2, 3, 3]]}\nrobot: {start: [2.5, 2.5]}\n"));
  });
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_NE(msg.find("robot.start"), std::string::npos) << msg;
  EXPECT_NE(msg.find("obstacle"), std::string::npos) << msg;
}

TEST(TextFile, WritesAtomically) {
  const std::string dir = testing::MakeTempDir();
  WriteFileAtomically(dir + "/f.txt", "one");
  WriteFileAtomically(dir + "/f.txt", "two");
  EXPECT_EQ(ReadTextFile(dir + "/f.txt", "file"), "two");
  size_t files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1u);  // no temporary left behind
}

// TUM trajectories as evo reads them: what navd writes reads back to the same poses (heading from
// the quaternion's yaw, any turn), comments and blank lines are skipped, and a line that is not
// eight numbers is refused with its file and line.
TEST(TumTrajectory, ReadsBackWhatItWritesAndNamesTheBadLine) {
  const std::vector<Pose2> poses = {{1.5, -2.25, 0.0}, {-3.0, 4.0, 3.0}, {0.125, 0.5, -2.5}};
  std::string text = "# t x y z qx qy qz qw\n\n";
  for (size_t k = 0; k < poses.size(); ++k) text += FormatTumLine(10.0 + k, poses[k]);
  const std::vector<Pose2> read = ParseTumTrajectory(text, "est.tum");
  ASSERT_EQ(read.size(), poses.size());
  for (size_t k = 0; k < poses.size(); ++k) {
    EXPECT_NEAR(read[k].x, poses[k].x, 1e-6);
    EXPECT_NEAR(read[k].y, poses[k].y, 1e-6);
    EXPECT_NEAR(NormalizeAngle(read[k].theta - poses[k].theta), 0.0, 1e-6);
  }
  // A quaternion with roll and pitch too: its yaw is what a planar pose keeps.
  const Eigen::Quaterniond q = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX());
  const std::string tilted = "1 2 3 0 " + std::to_string(q.x()) + " " + std::to_string(q.y()) + " " +
                             std::to_string(q.z()) + " " + std::to_string(q.w()) + "\n";
  EXPECT_NEAR(ParseTumTrajectory(tilted, "t").front().theta, 0.7, 1e-5);
  for (const char* bad : {"1 2 3 0 0 0 0\n", "1 2 3 0 0 0 0 1 extra\n", "1 nan 3 0 0 0 0 1\n"}) {
    try {
      ParseTumTrajectory(text + bad, "est.tum");
      ADD_FAILURE() << "accepted " << bad;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("est.tum:6:"), std::string::npos) << e.what();
    }
  }
}

// The PNG for people: a valid 8-bit grey PNG (signature, IHDR, CRCs, deflated rows) whose pixels
// are the map north up, in map_server's trinary shades.
TEST(MapPng, WritesTheMapNorthUpAsGreyPixels) {
  OccupancyGrid grid(5, 3, 0.1, {0, 0}, OccupancyGrid::kFree);
  grid.set({0, 2}, OccupancyGrid::kOccupied);  // top-left in the image
  grid.set({4, 0}, OccupancyGrid::kUnknown);   // bottom-right
  const std::string path = ::testing::TempDir() + "/map.png";
  SaveMapPng(grid, path);
  std::ifstream in(path, std::ios::binary);
  const std::string png((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  auto u32 = [&](size_t at) {
    return (uint32_t(uint8_t(png[at])) << 24) | (uint32_t(uint8_t(png[at + 1])) << 16) |
           (uint32_t(uint8_t(png[at + 2])) << 8) | uint32_t(uint8_t(png[at + 3]));
  };
  std::string idat, types;
  for (size_t at = 8; at < png.size();) {
    const uint32_t n = u32(at);
    const std::string type = png.substr(at + 4, 4);
    types += type + " ";
    EXPECT_EQ(u32(at + 8 + n), crc32(0L, reinterpret_cast<const Bytef*>(png.data() + at + 4), n + 4)) << type;
    if (type == "IHDR") {
      EXPECT_EQ(u32(at + 8), 5u);
      EXPECT_EQ(u32(at + 12), 3u);
      EXPECT_EQ(png[at + 16], 8);  // bit depth
      EXPECT_EQ(png[at + 17], 0);  // greyscale
    }
    if (type == "IDAT") idat += png.substr(at + 8, n);
    at += 12 + n;
  }
  EXPECT_EQ(types, "IHDR IDAT IEND ");
  std::string raw(3 * 6, '\0');
  uLongf size = raw.size();
  ASSERT_EQ(
      uncompress(reinterpret_cast<Bytef*>(raw.data()), &size, reinterpret_cast<const Bytef*>(idat.data()), idat.size()),
      Z_OK);
  ASSERT_EQ(size, 18u);
  EXPECT_EQ(uint8_t(raw[1]), 0);            // row 0 (top, y = 2), x = 0: occupied
  EXPECT_EQ(uint8_t(raw[2]), 254);          // free
  EXPECT_EQ(uint8_t(raw[2 * 6 + 5]), 205);  // row 2 (bottom, y = 0), x = 4: unknown
  EXPECT_THROW(SaveMapPng(OccupancyGrid(), path), Error);
}

}  // namespace
}  // namespace navd
