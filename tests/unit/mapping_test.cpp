// Occupancy grid mapping with known poses, the CARMEN log reader, and map_server writing.
#include <gtest/gtest.h>

#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <limits>

#include "services/common/carmen_log.h"
#include "services/common/carmen_odometry.h"
#include "services/common/error.h"
#include "services/common/map_server_format.h"
#include "services/common/scan_reach.h"
#include "services/common/world.h"
#include "services/mapping/log_renderer.h"
#include "services/mapping/occupancy_grid_mapper.h"
#include "services/mapping/path_walkers.h"
#include "simulator/laser_scanner.h"
#include "tests/support/process.h"

namespace navd {
namespace {

// Scans of navsim's warehouse from known poses rebuild its walls and its free space.
TEST(OccupancyGridMapper, RebuildsTheWarehouseFromKnownPoses) {
  const World world = DefaultWorld();
  LaserDescription laser = world.laser;
  laser.noise = 0.0;
  sim::LaserScanner scanner(laser);
  const RayCaster walls(world.map);
  std::mt19937_64 rng(1);
  mapping::OccupancyGridMapper mapper({0, 0}, {10, 10});
  for (const Pose2& p : {Pose2{0.8, 1.0, M_PI / 2}, Pose2{0.8, 5.0, -M_PI / 2}, Pose2{0.8, 8.0, 0.0},
                         Pose2{3.0, 2.6, 0.0}, Pose2{3.0, 2.6, M_PI}, Pose2{5.0, 5.0, 0.0}, Pose2{8.5, 8.5, M_PI}}) {
    std::vector<float> ranges = scanner.Scan(p, walls, {}, -1, rng);
    for (auto& r : ranges)
      if (r > laser.range_max) r = 50.0f;  // no return: only clears
    mapper.AddScan(p, ranges, scanner.angle_min(), scanner.increment());
  }
  const OccupancyGrid g = mapper.ToGrid();
  int agree = 0, disagree = 0;
  for (int y = 0; y < g.height(); ++y)
    for (int x = 0; x < g.width(); ++x) {
      const int8_t v = g.at({x, y});
      if (v < 0 || (v > 20 && v < 65)) continue;  // unknown or undecided
      (v >= 65) == world.map.IsOccupied({x, y}) ? ++agree : ++disagree;
    }
  EXPECT_GT(agree, 5000);
  EXPECT_LT(disagree, agree / 50);             // under 2% (wall faces seen at grazing angles)
  EXPECT_LT(g.at(g.CellOf({0.8, 3.0})), 20);   // corridor: free
  EXPECT_GE(g.at(g.CellOf({1.55, 3.0})), 65);  // corridor wall: occupied
}

TEST(MapServerFormat, SavesAtomicallyAndReadsBack) {
  const std::string dir = testing::MakeTempDir();
  OccupancyGrid g(4, 3, 0.1, Point2(-1.0, 2.0), OccupancyGrid::kUnknown);
  g.set({0, 0}, 100);
  g.set({1, 0}, 0);
  g.set({2, 2}, 10);
  SaveMapServerMap(g, dir + "/m.yaml");
  const OccupancyGrid back = LoadMapServerMap(dir + "/m.yaml");
  EXPECT_EQ(back.width(), 4);
  EXPECT_NEAR(back.origin().x(), -1.0, 1e-9);
  EXPECT_EQ(back.at({0, 0}), OccupancyGrid::kOccupied);
  EXPECT_EQ(back.at({1, 0}), OccupancyGrid::kFree);
  EXPECT_EQ(back.at({2, 2}), OccupancyGrid::kFree);
  EXPECT_EQ(back.at({3, 1}), OccupancyGrid::kUnknown);
  size_t files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 2u);  // m.yaml and m.pgm, no temporaries
}

std::string WriteGz(const std::string& path, const std::string& text) {
  gzFile f = gzopen(path.c_str(), "wb");
  gzwrite(f, text.data(), static_cast<unsigned>(text.size()));
  gzclose(f);
  return path;
}

TEST(CarmenLog, ReadsScansAndOdometryFromGzipAndReportsBadLines) {
  const std::string dir = testing::MakeTempDir();
  const std::string text =
      "# comment\n"
      "PARAM robot_frontlaser_offset 0.0 nohost 0\n"
      "ODOM 1 2 0.5 0 0 0 10.0 host 10.0\n"
      "FLASER 3 1.0 2.0 3.0 0.5 0.25 1.57 0.4 0.2 1.5 11.0 host 11.0\n"
      "FLASER 3 1.0 oops 3.0 0.5 0.25 1.57 0.4 0.2 1.5 12.0 host 12.0\n";
  const std::string path = WriteGz(dir + "/t.log.gz", text);
  const CarmenLog log = ReadCarmenLog(path);
  ASSERT_EQ(log.scans.size(), 1u);
  EXPECT_EQ(log.scans[0].ranges.size(), 3u);
  EXPECT_FLOAT_EQ(log.scans[0].ranges[2], 3.0f);
  EXPECT_NEAR(log.scans[0].pose.theta, 1.57, 1e-12);
  EXPECT_NEAR(log.scans[0].odometry.x, 0.4, 1e-12);
  EXPECT_DOUBLE_EQ(log.scans[0].timestamp, 11.0);
  ASSERT_EQ(log.odometry.size(), 1u);
  EXPECT_EQ(log.skipped_lines, 1);
  try {
    ReadCarmenLog(path, true);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("t.log.gz:5"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadCarmenLog(dir + "/missing.log"), Error);
  EXPECT_NEAR(CarmenBeamAngle(0, 181), -M_PI / 2, 1e-12);
  EXPECT_NEAR(CarmenBeamAngle(180, 181), M_PI / 2, 1e-12);
  EXPECT_NEAR(CarmenBeamAngle(179, 180), M_PI / 2 - M_PI / 180, 1e-12);  // 1 degree steps
  EXPECT_NEAR(CarmenBeamAngle(359, 360), M_PI / 2 - M_PI / 360, 1e-12);  // half a degree
  EXPECT_NEAR(CarmenBeamAngle(0, 401), -50 * M_PI / 180, 1e-12);         // 100 degrees centred ahead
  EXPECT_NEAR(CarmenBeamAngle(400, 401), 50 * M_PI / 180, 1e-12);
  EXPECT_NEAR(CarmenBeamAngle(1, 401) - CarmenBeamAngle(0, 401), M_PI / 720, 1e-12);
  EXPECT_NEAR(CarmenBeamAngle(0, 541), -M_PI / 2, 1e-12);  // any other count: 180 degrees
  EXPECT_NEAR(CarmenBeamAngle(540, 541), M_PI / 2, 1e-12);
  EXPECT_NEAR(CarmenBeamAngle(269, 270), M_PI / 2, 1e-12);
}

// A scanner's no-return reading (81.83 on the Intel log's SICK) piles up at one far range; the
// reader makes it the scans' range_max. A log without such a pile has none.
TEST(CarmenLog, InfersTheNoReturnReadingFromWhereReadingsPileUp) {
  std::string text;
  for (int k = 0; k < 4; ++k) text += "FLASER 4 1.0 81.83 2.5 81.83 0 0 0 0 0 0 " + std::to_string(k) + " host 0\n";
  CarmenLog log = ParseCarmenLog(text, "piles");
  EXPECT_NEAR(log.scans[0].range_max, 0.99 * 81.83, 1e-4);
  text = "FLASER 4 1.0 30.5 2.5 7.0 0 0 0 0 0 0 1 host 0\n";
  log = ParseCarmenLog(text, "no pile");
  EXPECT_EQ(log.scans[0].range_max, 0.0);
}

// Raw logs: each scan's odometry from the ODOM lines next to it in the file, interpolated by stamp
// when the stamps allow; ODOM lines stamped 0 (corrected logs echo the corrected pose so) are not
// odometry; repeated stamps follow the file; without ODOM lines, FLASER's own odometry fields.
TEST(CarmenOdometry, InterpolatesOdomLinesToEachScanAndFollowsTheFileWhenStampsRepeat) {
  const std::string text =
      "ODOM 7 7 1 0 0 0 9.0 h 9.0\n"
      "ODOM 0 0 0 0 0 0 10.0 h 10.0\n"
      "FLASER 1 1.0 9 9 1 5 5 0.5 11.5 h 11.5\n"  // between its neighbours by stamp: 3/4 of the way
      "ODOM 9 9 1 0 0 0 0 h 0\n"                  // an echo of the corrected pose: not odometry
      "ODOM 2 0 0.2 0 0 0 12.0 h 12.0\n"
      "ODOM 4 0 0.4 0 0 0 13.0 h 13.0\n"
      "ODOM 5 0 0.4 0 0 0 13.0 h 13.0\n"
      "FLASER 1 1.0 9 9 1 5 5 0.5 13.0 h 13.0\n"  // repeated stamps: the line before it
      "ODOM 6 0 0.4 0 0 0 13.0 h 13.0\n";
  const CarmenLog log = ParseCarmenLog(text, "raw");
  const std::vector<Pose2> odometry = OdometryAtScans(log);
  ASSERT_EQ(odometry.size(), 2u);
  EXPECT_NEAR(odometry[0].x, 1.5, 1e-9);
  EXPECT_NEAR(odometry[0].theta, 0.15, 1e-9);
  EXPECT_NEAR(odometry[1].x, 5.0, 1e-9);
  const CarmenLog fields = ParseCarmenLog("FLASER 1 1.0 9 9 1 5 6 0.5 11.5 h 11.5\n", "fields");
  const Pose2 own = OdometryAtScans(fields).at(0);
  EXPECT_NEAR(own.x, 5.0, 1e-9);
  EXPECT_NEAR(own.y, 6.0, 1e-9);
  EXPECT_NEAR(own.theta, 0.5, 1e-9);
}

// Paired by place in the file, a scan takes the share of the way between the ODOM lines next to
// it, but by stamp across a gap in the odometry (over max_gap) and where two scans share their
// two lines (they would take one pose). "stamp", "auto" and shares parse; anything else is refused.
TEST(CarmenOdometry, PairsByPlaceInTheFileButByStampAcrossGapsAndSharedLines) {
  const std::string text =
      "ODOM 0 0 0 0 0 0 10.0 h 10.0\n"
      "FLASER 1 1.0 9 9 0 9 9 0 10.0 h 10.0\n"  // halfway: 0.5
      "ODOM 1 0 0 0 0 0 10.2 h 10.2\n"
      "FLASER 1 1.0 9 9 0 9 9 0 10.2 h 10.2\n"  // 4.8 s to the next line: by stamp, 1
      "ODOM 3 0 0 0 0 0 15.0 h 15.0\n"
      "FLASER 1 1.0 9 9 0 9 9 0 15.0 h 15.0\n"  // shares its lines with the next scan: by stamp, 3
      "FLASER 1 1.0 9 9 0 9 9 0 15.1 h 15.1\n"  // and 3.5
      "ODOM 4 0 0 0 0 0 15.2 h 15.2\n";
  const CarmenLog log = ParseCarmenLog(text, "pairing");
  const std::vector<Pose2> odometry = OdometryAtScans(log, *ParseOdometryPairing("0.5", "--pairing"));
  ASSERT_EQ(odometry.size(), 4u);
  EXPECT_NEAR(odometry[0].x, 0.5, 1e-9);
  EXPECT_NEAR(odometry[1].x, 1.0, 1e-9);
  EXPECT_NEAR(odometry[2].x, 3.0, 1e-9);
  EXPECT_NEAR(odometry[3].x, 3.5, 1e-9);
  EXPECT_FALSE(ParseOdometryPairing("auto", "--pairing").has_value());
  EXPECT_TRUE(ParseOdometryPairing("stamp", "--pairing")->by_stamp);
  EXPECT_FALSE(std::signbit(ParseOdometryPairing("-0", "--pairing")->position));
  for (const char* bad : {"", "later", "1.5", "-0.1", "nan", " 0.5", "0.5x"})
    EXPECT_THROW(ParseOdometryPairing(bad, "--pairing"), Error) << bad;
}

// The scans' origin is the scanner's: a log whose PARAM puts it 0.2 m ahead of the centre has its
// odometry carried there, so turning on the spot moves it on a 0.2 m circle.
TEST(CarmenOdometry, IsCarriedToTheFrontLaserThatTheParamPlaces) {
  const std::string text =
      "PARAM robot_frontlaser_offset 0.2 nohost 0\n"
      "ODOM 1 1 0 0 0 0 10.0 h 10.0\n"
      "FLASER 1 1.0 9 9 1 1 1 0 10.0 h 10.0\n"
      "ODOM 1 1 1.5707963267948966 0 0 0 11.0 h 11.0\n"
      "FLASER 1 1.0 9 9 1 1 1 1.5707963267948966 11.0 h 11.0\n";
  const CarmenLog log = ParseCarmenLog(text, "offset");
  EXPECT_DOUBLE_EQ(log.front_laser_offset, 0.2);
  const std::vector<Pose2> odometry = OdometryAtScans(log);
  ASSERT_EQ(odometry.size(), 2u);
  EXPECT_NEAR(odometry[0].x, 1.2, 1e-9);
  EXPECT_NEAR(odometry[0].y, 1.0, 1e-9);
  EXPECT_NEAR(odometry[1].x, 1.0, 1e-9);
  EXPECT_NEAR(odometry[1].y, 1.2, 1e-9);
  EXPECT_NEAR(odometry[1].theta, M_PI / 2, 1e-9);
  // A PARAM whose value is not a number is a malformed line.
  EXPECT_THROW(ParseCarmenLog("PARAM robot_frontlaser_offset abc h 0\n" + text, "bad", true), Error);
  EXPECT_DOUBLE_EQ(ParseCarmenLog("PARAM robot_frontlaser_offset abc h 0\n" + text, "lenient").front_laser_offset, 0.2);
}

// A log logged without the robot's laser messages: its RAWLASER1 scans (their own angles and
// maximum) are placed where the ODOM lines put the scanner at their stamps, the centre's pose as
// their odometry. Beside FLASER or ROBOTLASER1 lines they are the same scans again and are left
// out; without stamped ODOM lines nothing can place them, and reading says so.
TEST(CarmenLog, PlacesRawLaserScansByTheOdometryAtTheirStamps) {
  const std::string odom =
      "PARAM robot_frontlaser_offset 0.2 nohost 0\n"
      "ODOM 0 0 0 0 0 0 10.0 h 10.0\n"
      "RAWLASER1 0 -1.5 3.0 0.75 30.0 0.01 0 5 1 2 3 4 30 0 10.5 h 10.5\n"
      "ODOM 2 0 1.0 0 0 0 11.0 h 11.0\n"
      "RAWLASER1 0 -1.5 3.0 0.75 30.0 0.01 0 5 1 2 3 4 5 2 0.5 0.5 11.0 h 11.0\n";
  const CarmenLog log = ParseCarmenLog(odom, "raw", true);
  ASSERT_EQ(log.scans.size(), 2u);
  EXPECT_EQ(log.scans[0].ranges.size(), 5u);
  EXPECT_DOUBLE_EQ(log.scans[0].angle_min, -1.5);
  EXPECT_DOUBLE_EQ(log.scans[0].angle_increment, 0.75);
  EXPECT_DOUBLE_EQ(log.scans[0].range_max, 30.0);
  EXPECT_DOUBLE_EQ(log.scans[1].timestamp, 11.0);
  // Halfway between the ODOM lines: the centre at (1, 0) turned 0.5 rad, the scanner 0.2 m ahead.
  EXPECT_NEAR(log.scans[0].odometry.x, 1.0, 1e-9);
  EXPECT_NEAR(log.scans[0].odometry.theta, 0.5, 1e-9);
  EXPECT_NEAR(log.scans[0].pose.x, 1.0 + 0.2 * std::cos(0.5), 1e-9);
  EXPECT_NEAR(log.scans[0].pose.y, 0.2 * std::sin(0.5), 1e-9);
  EXPECT_NEAR(log.scans[1].pose.x, 2.0 + 0.2 * std::cos(1.0), 1e-9);
  const std::vector<Pose2> odometry = OdometryAtScans(log);
  EXPECT_NEAR(odometry[1].y, log.scans[1].pose.y, 1e-9);

  const CarmenLog posed = ParseCarmenLog(odom + "FLASER 3 1.0 2.0 3.0 0.5 0.25 1.57 0.4 0.2 1.5 11.0 h 11.0\n", "both");
  ASSERT_EQ(posed.scans.size(), 1u);
  EXPECT_EQ(posed.scans[0].ranges.size(), 3u);

  try {
    ParseCarmenLog("RAWLASER1 0 -1.5 3.0 0.75 30.0 0.01 0 5 1 2 3 4 5 0 10.5 h 10.5\n", "no odometry");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no stamped ODOM"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseCarmenLog("RAWLASER1 0 -1.5 3.0 0.75 30.0 0.01 0 5 1 2 3\n" + odom, "short", true), Error);
}

// A logger that writes the front laser's old and new messages writes each scan as a FLASER and a
// ROBOTLASER1 line of one stamp: it is read once, from the ROBOTLASER1 line. FLASER lines no
// ROBOTLASER1 line shares a stamp with (logs joined from two loggers) are read too. A rear laser's
// RLASER lines are passed over.
TEST(CarmenLog, ReadsAScanWrittenAsFlaserAndRobotLaserOnce) {
  std::string text;
  for (int k = 0; k < 3; ++k) {
    const std::string x = std::to_string(k), stamp = std::to_string(10 + k);
    text += "FLASER 3 7.0 8.0 9.0 " + x + " 5 0 " + x + " 5 0 " + stamp + " h " + stamp + "\n";
    text += "RLASER 3 4.0 5.0 6.0 " + x + " 0 3.14 " + x + " 0 0 " + stamp + " h " + stamp + "\n";
    text += "ROBOTLASER1 0 -0.5 1.0 0.5 30.0 0.01 0 3 1.0 2.0 3.0 0 " + x + " 0 0 " + x + " 0 0 0 0 0 0 0 " + stamp +
            " h " + stamp + "\n";
  }
  const CarmenLog log = ParseCarmenLog(text, "both", true);
  ASSERT_EQ(log.scans.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_DOUBLE_EQ(log.scans[k].pose.x, k);
    EXPECT_DOUBLE_EQ(log.scans[k].pose.y, 0.0);
    EXPECT_DOUBLE_EQ(log.scans[k].angle_min, -0.5);
    EXPECT_DOUBLE_EQ(log.scans[k].angle_increment, 0.5);
    EXPECT_FLOAT_EQ(log.scans[k].ranges[0], 1.0f);
  }
  // Two FLASER scans of other stamps: both read, in file order, their beams placed by the count.
  const CarmenLog joined = ParseCarmenLog(
      "FLASER 3 7.0 8.0 9.0 9 5 0 9 5 0 3.0 h 3.0\n" + text + "FLASER 3 7.0 8.0 9.0 9 5 0 9 5 0 20.0 h 20.0\n",
      "joined", true);
  ASSERT_EQ(joined.scans.size(), 5u);
  EXPECT_FLOAT_EQ(joined.scans.front().ranges[0], 7.0f);
  EXPECT_DOUBLE_EQ(joined.scans.front().angle_min, CarmenBeamAngle(0, 3));
  EXPECT_FLOAT_EQ(joined.scans.back().ranges[0], 7.0f);
  EXPECT_DOUBLE_EQ(joined.scans.back().timestamp, 20.0);
  EXPECT_DOUBLE_EQ(joined.scans[1].angle_min, -0.5);
}

// A log whose stamps cannot time its scans (most repeat) gets them paced from its odometry; a log
// with usable stamps keeps them.
TEST(CarmenLogStamps, CoarseStampsArePacedFromOdometry) {
  const std::string text =
      "FLASER 1 1.0 0 0 0 0 0 0 1.13486e+09 h 1.13486e+09\n"
      "FLASER 1 1.0 1 0 0 1 0 0 1.13486e+09 h 1.13486e+09\n"         // 1 m: 2 s at 0.5 m/s
      "FLASER 1 1.0 1 0 1 1 0 1 1.13486e+09 h 1.13486e+09\n"         // 1 rad: 2 s at 0.5 rad/s
      "FLASER 1 1.0 1 0 1 1 0 1 1.13487e+09 h 1.13487e+09\n"         // still: the least gap
      "FLASER 1 1.0 1 0.05 1 1 0.05 1 1.13487e+09 h 1.13487e+09\n";  // 5 cm: 0.1 s, raised to the least gap
  CarmenLog log = ParseCarmenLog(text, "coarse");
  ASSERT_TRUE(PaceScansWhenStampsAreCoarse(log));
  const double t0 = 1.13486e+09;
  EXPECT_DOUBLE_EQ(log.scans[0].timestamp, t0);
  EXPECT_NEAR(log.scans[1].timestamp - t0, 2.0, 1e-6);
  EXPECT_NEAR(log.scans[2].timestamp - t0, 4.0, 1e-6);
  EXPECT_NEAR(log.scans[3].timestamp - t0, 4.2, 1e-6);
  EXPECT_NEAR(log.scans[4].timestamp - t0, 4.4, 1e-6);
  CarmenLog fine = ParseCarmenLog(
      "FLASER 1 1.0 0 0 0 0 0 0 10.0 h 10.0\nFLASER 1 1.0 1 0 0 1 0 0 10.5 h 10.5\n"
      "FLASER 1 1.0 2 0 0 2 0 0 10.5 h 10.5\n",
      "fine");
  EXPECT_FALSE(PaceScansWhenStampsAreCoarse(fine));
  EXPECT_DOUBLE_EQ(fine.scans[2].timestamp, 10.5);
  // A log that is fine but for a stamp that repeats, or goes back, is put in its file's order, a
  // scan at least as long after the one before as its motion takes at 3 m/s and 4 rad/s: 1 m
  // and 0.6 rad in 10 ms come 0.33 and 0.15 s after it.
  EXPECT_EQ(TimeScansInFileOrder(fine), 1);
  EXPECT_NEAR(fine.scans[2].timestamp, 10.5 + 1.0 / 3.0, 1e-9);
  CarmenLog back = ParseCarmenLog(
      "FLASER 1 1.0 0 0 0 0 0 0 10.0 h 10.0\nFLASER 1 1.0 1 0 0 1 0 0 11.0 h 11.0\n"
      "FLASER 1 1.0 1 0 0.6 1 0 0.6 11.01 h 11.01\nFLASER 1 1.0 1 0 0.6 1 0 0.6 10.9 h 10.9\n"
      "FLASER 1 1.0 2 0 0.6 2 0 0.6 13.0 h 13.0\n",
      "back");
  EXPECT_EQ(TimeScansInFileOrder(back), 2);
  EXPECT_NEAR(back.scans[2].timestamp, 11.15, 1e-9);
  EXPECT_NEAR(back.scans[3].timestamp, 11.151, 1e-9);
  EXPECT_DOUBLE_EQ(back.scans[4].timestamp, 13.0);
  EXPECT_EQ(TimeScansInFileOrder(back), 0);
}

// Scans keep their place in the file whatever their stamps say (logs with fake, repeated stamps).
TEST(CarmenLog, KeepsScansInFileOrderWhenStampsRepeatOrGoBack) {
  const std::string text =
      "FLASER 1 1.0 0 0 0 0 0 0 5.0 h 5.0\n"
      "FLASER 1 2.0 0 0 0 0 0 0 5.0 h 5.0\n"
      "FLASER 1 3.0 0 0 0 0 0 0 4.0 h 4.0\n";
  const CarmenLog log = ParseCarmenLog(text, "stamps");
  ASSERT_EQ(log.scans.size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(log.scans[k].ranges[0], 1.0f + k);
}

// A log that states its front laser's field of view and beam spacing places its FLASER beams by
// them (CARMEN's driver: from -fov / 2, a resolution apart), in radians or degrees as CARMEN
// versions write the fov; a log that does not, or states a 180-degree SICK's, keeps the guess from
// the beam count; a resolution the beam count contradicts gives way to the fov.
TEST(CarmenLog, PlacesFlaserBeamsWhereTheFrontLasersParamsSay) {
  const double deg = M_PI / 180.0;
  auto expect = [&](FlaserBeamLayout got, double min_deg, double step_deg, const char* what) {
    EXPECT_NEAR(got.angle_min, min_deg * deg, 1e-9) << what;
    EXPECT_NEAR(got.angle_increment, step_deg * deg, 1e-9) << what;
  };
  expect(FlaserBeams(181), -90, 1, "no PARAM");
  expect(FlaserBeams(360, 0.0, 0.5 * deg), -90, 0.5, "a resolution alone: the count says");
  expect(FlaserBeams(401, 0.0, 0.25 * deg), -50, 0.25, "a resolution alone: the count says (100-degree mode)");
  expect(FlaserBeams(361, M_PI, 0.5 * deg), -90, 0.5, "a SICK's 180 degrees");
  expect(FlaserBeams(360, M_PI, 0.5 * deg), -90, 0.5, "a SICK's 180 degrees less its last beam");
  expect(FlaserBeams(180, M_PI), -90, 1, "180 degrees, no resolution: the count says");
  expect(FlaserBeams(241, 240 * deg), -120, 1, "a fov alone");
  expect(FlaserBeams(682, 240 * deg, 0.352 * deg), -120, 0.352, "a Hokuyo");
  expect(FlaserBeams(720, 360 * deg), -180, 0.5, "a whole turn: as many gaps as beams");
  expect(FlaserBeams(361, M_PI, 1.0 * deg), -90, 0.5, "a resolution too wide for the count");
  expect(FlaserBeams(181, M_PI, 0.5 * deg), -90, 1, "a resolution too fine for the count");
  expect(FlaserBeams(361, M_PI, 0.0087), -90, 0.5, "a resolution in radians");
  expect(FlaserBeams(241, 240 * deg, 0.5 * deg), -120, 1, "a resolution too fine for another fov");

  // An n-beam FLASER line, every beam 2 m.
  auto flaser = [](int n) {
    std::string line = "FLASER " + std::to_string(n);
    for (int i = 0; i < n; ++i) line += " 2.0";
    return line + " 0 0 0 0 0 0 10.0 h 10.0\n";
  };
  const std::string scans = flaser(241);
  // The PARAM line may come after the scans it describes.
  for (const std::string param :
       {"PARAM laser_front_laser_fov 240 h 0\n", "PARAM laser_front_laser_fov 4.18879 h 0\n"}) {
    const CarmenLog log = ParseCarmenLog(scans + param + scans, "fov", true);
    ASSERT_EQ(log.scans.size(), 2u);
    EXPECT_NEAR(log.front_laser_fov, 240 * deg, 1e-12) << param;
    for (const CarmenScan& s : log.scans) {
      EXPECT_NEAR(s.angle_min, -120 * deg, 1e-12) << param;
      EXPECT_NEAR(s.angle_increment, deg, 1e-12) << param;
    }
    // Written back with its PARAM lines, it reads back the same.
    const CarmenLog back = ParseCarmenLog(FormatFlaserLog(log, "test"), "back", true);
    ASSERT_EQ(back.scans.size(), 2u);
    EXPECT_NEAR(back.scans[1].angle_min, log.scans[1].angle_min, 1e-9);
    EXPECT_NEAR(back.scans[1].angle_increment, log.scans[1].angle_increment, 1e-12);
  }
  // csail's PARAM lines (3.14159 rad, 0.5 degrees) place its 361 beams exactly where the count does.
  const CarmenLog sick = ParseCarmenLog(
      "PARAM laser_front_laser_resolution 0.5 h 0\nPARAM laser_front_laser_fov 3.14159 h 0\n" + flaser(361), "sick",
      true);
  EXPECT_EQ(sick.scans[0].angle_min, CarmenBeamAngle(0, 361));
  EXPECT_EQ(sick.scans[0].angle_increment, CarmenBeamAngle(1, 361) - CarmenBeamAngle(0, 361));
  for (const std::string bad :
       {"PARAM laser_front_laser_fov abc h 0\n", "PARAM laser_front_laser_fov -3 h 0\n",
        "PARAM laser_front_laser_fov 400 h 0\n", "PARAM laser_front_laser_resolution 0 h 0\n"}) {
    try {
      ParseCarmenLog(bad + scans, "bad", true);
      ADD_FAILURE() << bad;
    } catch (const Error& e) {  // the parameter named
      EXPECT_NE(std::string(e.what()).find(bad.substr(6, bad.find(' ', 6) - 6)), std::string::npos) << e.what();
    }
    EXPECT_NEAR(ParseCarmenLog(bad + scans, "lenient").scans[0].angle_min, -90 * deg, 1e-12) << bad;
  }
}

// A FLASER line reads back as the scan it was made from; a scan whose beams FLASER cannot say is
// refused, not written at the wrong angles.
TEST(CarmenLog, FlaserLinesReadBackAsTheScanTheyWereMadeFrom) {
  CarmenScan scan;
  for (int i = 0; i < 181; ++i) scan.ranges.push_back(1.0f + 0.01f * i);
  scan.angle_min = CarmenBeamAngle(0, 181);
  scan.angle_increment = CarmenBeamAngle(1, 181) - CarmenBeamAngle(0, 181);
  scan.pose = {1.5, -2.25, 0.75};
  scan.odometry = {10.0, 20.0, -3.0};
  scan.timestamp = 1234.5678;
  const CarmenLog log = ParseCarmenLog(FormatFlaserLine(scan, "test") + FormatFlaserLine(scan, "test"), "lines", true);
  ASSERT_EQ(log.scans.size(), 2u);
  const CarmenScan& back = log.scans[0];
  ASSERT_EQ(back.ranges.size(), 181u);
  for (size_t i = 0; i < back.ranges.size(); ++i) EXPECT_NEAR(back.ranges[i], scan.ranges[i], 1e-3) << i;
  EXPECT_NEAR(back.angle_min, scan.angle_min, 1e-12);
  EXPECT_NEAR(back.angle_increment, scan.angle_increment, 1e-12);
  EXPECT_NEAR(back.pose.x, 1.5, 1e-6);
  EXPECT_NEAR(back.pose.y, -2.25, 1e-6);
  EXPECT_NEAR(back.pose.theta, 0.75, 1e-6);
  EXPECT_NEAR(back.odometry.theta, -3.0, 1e-6);
  EXPECT_NEAR(back.timestamp, 1234.5678, 1e-6);
  scan.angle_min = -2.0;  // a 240-degree scanner's first beam
  try {
    FormatFlaserLine(scan, "test");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("181 beams are read back from -90.00 degrees, 1.0000 apart; these start at "
                                         "-114.59"),
              std::string::npos)
        << e.what();
  }
}

// Logs converted from ROS write inf for a no-return and nan for no reading: the lines are read
// (not skipped as malformed), and the no-return reading is still inferred from the finite ones.
TEST(CarmenLog, ReadsInfAndNanReadings) {
  std::string text;
  for (int k = 0; k < 6; ++k) text += "FLASER 4 1.0 inf 81.83 nan 0 0 0 0 0 0 " + std::to_string(k) + " host 0\n";
  const CarmenLog log = ParseCarmenLog(text, "ros", true);
  ASSERT_EQ(log.scans.size(), 6u);
  EXPECT_EQ(log.skipped_lines, 0);
  EXPECT_TRUE(std::isinf(log.scans[0].ranges[1]));
  EXPECT_TRUE(std::isnan(log.scans[0].ranges[3]));
  EXPECT_NEAR(log.scans[0].range_max, 0.99 * 81.83, 1e-4);
  EXPECT_EQ(ParseCarmenLog(text + "FLASER 2 1.0 infinite 0 0 0 0 0 0 1 h 1\n", "bad").skipped_lines, 1);
  EXPECT_EQ(ParseCarmenLog(text + "FLASER 2 1.0 1e400 0 0 0 0 0 0 1 h 1\n", "overflow").skipped_lines, 1);
}

// A 401-beam FLASER line is the SICK's 100-degree mode: 0.25 degrees apart, centred ahead.
TEST(CarmenLog, ReadsAHundredDegreeScanCentredAhead) {
  std::string line = "FLASER 401";
  for (int i = 0; i < 401; ++i) line += " 2.0";
  const CarmenLog log = ParseCarmenLog(line + " 0 0 0 0 0 0 1.0 h 1.0\n", "narrow", true);
  ASSERT_EQ(log.scans.size(), 1u);
  EXPECT_NEAR(log.scans[0].angle_min, -50 * M_PI / 180, 1e-9);
  EXPECT_NEAR(log.scans[0].angle_increment, 0.25 * M_PI / 180, 1e-9);
}

}  // namespace
}  // namespace navd

namespace navd::mapping {
namespace {

// HIMM (book ch. 4): +3 per reading ending in a cell, -1 per reading through it, 0..15; the map
// shows certainty / 15, so a wall needs four readings to count as an obstacle.
TEST(MapperRules, HimmCountsReadingsUpToFifteen) {
  MapperOptions o;
  o.rule = MapUpdateRule::kHimm;
  OccupancyGridMapper mapper({0.0, 0.0}, {4.0, 4.0}, o);
  const Pose2 pose{0.5, 2.0, 0.0};
  const std::vector<float> one_beam{2.0f};
  mapper.AddScan(pose, one_beam, 0.0, 0.01);
  OccupancyGrid g = mapper.ToGrid();
  EXPECT_EQ(g.at(g.CellOf({2.5 + 0.01, 2.0})), 20);  // 3 / 15
  EXPECT_EQ(g.at(g.CellOf({1.5, 2.0})), 0);
  EXPECT_EQ(g.at(g.CellOf({3.5, 2.0})), OccupancyGrid::kUnknown);
  for (int i = 0; i < 10; ++i) mapper.AddScan(pose, one_beam, 0.0, 0.01);
  g = mapper.ToGrid();
  EXPECT_EQ(g.at(g.CellOf({2.5 + 0.01, 2.0})), 100);  // capped at 15
  EXPECT_TRUE(g.IsOccupied(g.CellOf({2.5 + 0.01, 2.0})));
  // A person walked away: readings now pass through, one certainty step at a time.
  const std::vector<float> longer{3.0f};
  for (int i = 0; i < 4; ++i) mapper.AddScan(pose, longer, 0.0, 0.01);
  g = mapper.ToGrid();
  EXPECT_EQ(g.at(g.CellOf({2.5 + 0.01, 2.0})), 73);  // 11 / 15
}

// Elfes' sonar cone: free inside, occupied on the arc, the axis weighted most.
TEST(MapperRules, SonarConeClearsInsideAndMarksTheArc) {
  OccupancyGridMapper mapper({0.0, 0.0}, {5.0, 5.0}, {});
  const Pose2 sensor{0.5, 2.5, 0.0};
  const double half_angle = 15.0 * M_PI / 180.0;
  for (int i = 0; i < 5; ++i) mapper.AddSonar(sensor, 3.0, half_angle, 5.0);
  const OccupancyGrid g = mapper.ToGrid();
  EXPECT_TRUE(g.IsOccupied(g.CellOf({3.5, 2.5})));                 // on the axis, at the reading
  EXPECT_GT(g.at(g.CellOf({3.45, 2.9})), 50);                      // on the arc, off axis
  EXPECT_LT(g.at(g.CellOf({2.0, 2.5})), 30);                       // inside: free
  EXPECT_EQ(g.at(g.CellOf({2.0, 4.0})), OccupancyGrid::kUnknown);  // outside the cone
  EXPECT_EQ(g.at(g.CellOf({4.5, 2.5})), OccupancyGrid::kUnknown);  // beyond the reading
  // A no-return only clears.
  OccupancyGridMapper clear({0.0, 0.0}, {5.0, 5.0}, {});
  clear.AddSonar(sensor, 6.0, half_angle, 5.0);
  const OccupancyGrid c = clear.ToGrid();
  EXPECT_LT(c.at(c.CellOf({3.5, 2.5})), 50);
}

// Seed 002's local-to-global fusion: a robot-centred local map, turned and shifted, lands in the
// global map where it belongs.
TEST(MapperRules, LocalMapsFuseIntoTheGlobalMapByInterpolation) {
  OccupancyGrid local(40, 40, 0.05, Point2::Zero(), OccupancyGrid::kUnknown);
  local.FillBox({0.0, 0.0}, {2.0, 2.0}, 10);  // seen free
  local.FillBox({1.5, 0.0}, {1.6, 2.0}, 95);  // a wall 1.5 m ahead
  OccupancyGridMapper global({0.0, 0.0}, {6.0, 6.0}, {});
  const Pose2 where{3.0, 1.0, M_PI / 2};  // the local x axis points up the map
  global.FuseLocalMap(local, where);
  global.FuseLocalMap(local, where);
  const OccupancyGrid g = global.ToGrid();
  EXPECT_TRUE(g.IsOccupied(g.CellOf({2.0, 2.55})));                // the wall, 1.5 m up from y = 1
  EXPECT_LT(g.at(g.CellOf({2.0, 1.8})), 10);                       // free before it
  EXPECT_EQ(g.at(g.CellOf({4.0, 2.0})), OccupancyGrid::kUnknown);  // right of the footprint
  MapperOptions himm;
  himm.rule = MapUpdateRule::kHimm;
  OccupancyGridMapper h({0.0, 0.0}, {6.0, 6.0}, himm);
  EXPECT_THROW(h.FuseLocalMap(local, where), Error);
}

// A no-return reading (at the scanner's maximum) marks nothing and clears only
// missing_data_ray_length along its beam, however far the scanner could see.
TEST(MapperRules, NoReturnReadingsMarkNothingAndClearOnlyTheMissingDataRayLength) {
  MapperOptions o;
  o.missing_data_ray_length = 3.0;
  OccupancyGridMapper mapper({0.0, 0.0}, {20.0, 4.0}, o);
  const Pose2 pose{0.5, 2.0, 0.0};
  mapper.AddScan(pose, {81.83f}, 0.0, 0.01, 81.0);
  const OccupancyGrid g = mapper.ToGrid();
  EXPECT_LT(g.at(g.CellOf({2.0, 2.0})), 50);                       // cleared within 3 m
  EXPECT_EQ(g.at(g.CellOf({4.0, 2.0})), OccupancyGrid::kUnknown);  // nothing said beyond
  for (int x = 0; x < g.width(); ++x) EXPECT_FALSE(g.IsOccupied({x, g.CellOf({0, 2.0}).y}));

  // ROS's no-return, +inf, clears the same; NaN (no reading) says nothing.
  OccupancyGridMapper ros({0.0, 0.0}, {20.0, 4.0}, o);
  ros.AddScan(pose, {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()}, 0.0, M_PI / 2);
  const OccupancyGrid r = ros.ToGrid();
  EXPECT_LT(r.at(r.CellOf({2.0, 2.0})), 50);
  EXPECT_EQ(r.at(r.CellOf({4.0, 2.0})), OccupancyGrid::kUnknown);
  EXPECT_EQ(r.at(r.CellOf({0.5, 3.0})), OccupancyGrid::kUnknown);  // the NaN beam's way
}

// Readings of a few millimetres are a scanner's error codes (a Hokuyo's 0-19 mm), not echoes: they
// mark no obstacle at the scanner, clear nothing, count as no near echo and give SLAM no point.
TEST(MapperRules, ErrorCodeReadingsAreNoEchoes) {
  OccupancyGridMapper mapper({0.0, 0.0}, {4.0, 4.0});
  const Pose2 pose{2.0, 2.0, 0.0};
  std::vector<float> codes(180);
  for (size_t i = 0; i < codes.size(); ++i) codes[i] = 0.001f * static_cast<float>(i % 20);
  mapper.AddScan(pose, codes, -M_PI / 2, M_PI / 180);
  const OccupancyGrid g = mapper.ToGrid();
  for (int y = 0; y < g.height(); ++y)
    for (int x = 0; x < g.width(); ++x) EXPECT_EQ(g.at({x, y}), OccupancyGrid::kUnknown) << x << "," << y;
  EXPECT_EQ(ScanReach(codes, 81.91, {}), 50.0);  // no near echo: the scan found nothing
  EXPECT_TRUE(ScanReturns(codes, -M_PI / 2, M_PI / 180, 81.91, 20.0).empty());
  EXPECT_FALSE(IsEcho(0.019, 81.91));
  EXPECT_TRUE(IsEcho(kMinEchoRange, 81.91));
}

// A map's extent that the data decide gets the resolution asked for while it fits a grid, and the
// finest 5 mm step that does beyond.
TEST(MapperRules, ResolutionToFitCoarsensOnlyWhatAGridCannotHold) {
  EXPECT_EQ(ResolutionToFit({0, 0}, {100, 100}, 0.05), 0.05);
  EXPECT_NEAR(ResolutionToFit({0, 0}, {252, 252}, 0.05), 0.055, 1e-12);  // 25.4 M cells at 5 cm
  EXPECT_NEAR(ResolutionToFit({-1000, 0}, {1000, 50}, 0.02), 0.065, 1e-12);
  EXPECT_EQ(ResolutionToFit({0, 0}, {252, 252}, 0.1), 0.1);
  EXPECT_NEAR(ResolutionToFit({0, 0}, {4e6, 0.01}, 0.05), 0.16, 1e-12);  // one row of cells
  // A corrupt pose's extent is no map: left to the mapper to refuse, not searched for.
  EXPECT_EQ(ResolutionToFit({0, 0}, {1e18, 100}, 0.05), 0.05);
  EXPECT_EQ(ResolutionToFit({0, 0}, {std::numeric_limits<double>::quiet_NaN(), 100}, 0.05), 0.05);
}

// A wall seen head-on twice stays a wall when three beams graze through its cell on their way
// elsewhere (a shallow view along the wall from down a corridor).
TEST(MapperRules, AFewGrazingBeamsDoNotEraseAWall) {
  OccupancyGridMapper mapper({0.0, 0.0}, {10.0, 4.0});
  const Point2 wall_cell{5.025, 2.025};
  for (int k = 0; k < 2; ++k) mapper.AddScan({5.025, 0.5, M_PI / 2}, {1.5f}, 0.0, 0.01);  // ends in the cell
  // Beams along the wall's row that pass through the cell and end beyond it.
  for (int k = 0; k < 3; ++k) mapper.AddScan({1.0, 2.025, 0.0}, {7.0f}, 0.0, 0.01);
  const OccupancyGrid g = mapper.ToGrid();
  EXPECT_TRUE(g.IsOccupied(g.CellOf(wall_cell))) << static_cast<int>(g.at(g.CellOf(wall_cell)));
  EXPECT_FALSE(g.IsOccupied(g.CellOf({3.0, 2.025})));
}

// Echoes beyond the usable range (15 m) mark nothing in a scan that finds plenty nearer (a room's,
// one beam out through a door); in a scan that finds almost nothing near (an open hall's), they
// are all it has, and mark its far wall, out to the far reach (50 m).
TEST(MapperRules, FarEchoesMarkOnlyInAScanThatFindsTooLittleNear) {
  EXPECT_EQ(ScanReach(std::vector<float>(180, 5.0f), 81.91, {}), 20.0);
  EXPECT_EQ(ScanReach(std::vector<float>(180, 30.0f), 81.91, {}), 50.0);
  EXPECT_EQ(ScanReach(std::vector<float>(180, 81.91f), 81.91, {}), 50.0);  // no-returns are not echoes near
  // 100 near echoes: plenty for 361 beams, an open hall's few for 1081 (a third of that share).
  for (const size_t beams : {361u, 1081u}) {
    std::vector<float> ranges(beams, 30.0f);
    std::fill_n(ranges.begin(), 100, 5.0f);
    EXPECT_EQ(ScanReach(ranges, 81.91, {}), beams == 361u ? 20.0 : 50.0) << beams;
  }
  MapperOptions o;
  const Pose2 pose{1.0, 20.0, 0.0};
  const double increment = M_PI / 180.0, angle_min = -M_PI / 2;
  std::vector<float> hall(180, 30.0f), room(180, 4.0f);
  room[90] = 30.0f;  // straight ahead, through the door
  OccupancyGridMapper in_hall({0.0, 0.0}, {40.0, 40.0}, o), in_room({0.0, 0.0}, {40.0, 40.0}, o);
  in_hall.AddScan(pose, hall, angle_min, increment);
  in_room.AddScan(pose, room, angle_min, increment);
  const OccupancyGrid h = in_hall.ToGrid(), r = in_room.ToGrid();
  EXPECT_TRUE(h.IsOccupied(h.CellOf({31.0 + 0.01, 20.0})));
  EXPECT_LT(h.at(h.CellOf({25.0, 20.0})), 50);  // cleared on the way
  EXPECT_EQ(r.at(r.CellOf({31.0 + 0.01, 20.0})), OccupancyGrid::kUnknown);
  EXPECT_EQ(r.at(r.CellOf({25.0, 20.0})), OccupancyGrid::kUnknown);  // traced to 15 m only
}

// A box room 10 m x 8 m (walls one cell thick on its edges, a 1 m gap in the east wall) and a log
// of two scans in it: rendered, the scans read the distances to its walls from the log's poses, or
// from poses every step between them.
TEST(LogRenderer, CastsTheLogsBeamsInTheMapAtItsPosesOrBetweenThem) {
  OccupancyGrid room(200, 160, 0.05, {0.0, 0.0});
  for (int x = 0; x < 200; ++x)
    room.set({x, 0}, OccupancyGrid::kOccupied), room.set({x, 159}, OccupancyGrid::kOccupied);
  for (int y = 0; y < 160; ++y) {
    room.set({0, y}, OccupancyGrid::kOccupied);
    if (y < 70 || y >= 90) room.set({199, y}, OccupancyGrid::kOccupied);
  }
  const RayCaster world(room);
  CarmenLog log;
  for (const auto& [x, stamp] : {std::pair{3.0, 10.0}, std::pair{5.0, 12.0}}) {
    CarmenScan s;
    s.ranges.assign(181, 1.0f);
    s.angle_min = -M_PI / 2;
    s.angle_increment = M_PI / 180;
    s.pose = {x, 2.0, 0.0};
    s.timestamp = stamp;
    log.scans.push_back(s);
  }
  LogRenderOptions o;
  o.range_noise = 0.0;
  const CarmenLog at_poses = RenderLog(log, world, o);
  ASSERT_EQ(at_poses.scans.size(), 2u);
  const CarmenScan& first = at_poses.scans[0];
  EXPECT_DOUBLE_EQ(first.pose.x, 3.0);
  EXPECT_DOUBLE_EQ(first.odometry.x, 3.0);
  EXPECT_DOUBLE_EQ(first.pose.y, 2.0);
  EXPECT_DOUBLE_EQ(first.timestamp, 10.0);
  EXPECT_NEAR(first.ranges[0], 2.0 - 0.05, 0.06);                            // south wall, beam -90 degrees
  EXPECT_NEAR(first.ranges[180], 8.0 - 2.0 - 0.05, 0.06);                    // north wall, beam +90 degrees
  EXPECT_NEAR(first.ranges[135], (8.0 - 0.05 - 2.0) * std::sqrt(2.0), 0.1);  // north wall at 45 degrees
  EXPECT_DOUBLE_EQ(first.range_max, o.no_return);
  // Straight ahead from (5, 2) along y = 2 hits the east wall; from (5, 4) the beam leaves through the gap.
  EXPECT_NEAR(at_poses.scans[1].ranges[90], 10.0 - 0.05 - 5.0, 0.06);
  CarmenLog gap = log;
  gap.scans[1].pose.y = 4.0;
  EXPECT_FLOAT_EQ(RenderLog(gap, world, o).scans[1].ranges[90], static_cast<float>(o.no_return));

  o.step = 0.5;
  o.range_noise = 0.01;
  const CarmenLog dense = RenderLog(log, world, o);
  ASSERT_EQ(dense.scans.size(), 5u);  // 2 m in 0.5 m steps, and the last pose
  for (size_t k = 0; k < dense.scans.size(); ++k) {
    EXPECT_NEAR(dense.scans[k].pose.x, 3.0 + 0.5 * k, 1e-9);
    EXPECT_NEAR(dense.scans[k].timestamp, 10.0 + 0.5 * k, 1e-9);
  }
  // The noise is the noise asked for: about 1 cm around the noiseless ranges.
  double sum = 0.0, sum_sq = 0.0;
  for (size_t i = 0; i < 181; ++i) {
    const double d = dense.scans[0].ranges[i] - first.ranges[i];
    sum += d;
    sum_sq += d * d;
  }
  EXPECT_NEAR(sum / 181, 0.0, 0.003);
  EXPECT_NEAR(std::sqrt(sum_sq / 181), 0.01, 0.003);
  o.step = -1.0;
  EXPECT_THROW(RenderLog(log, world, o), Error);
}

TEST(LogRenderer, RendersAnotherScannersBeamsWhereTheRenderedLogIsReadBack) {
  OccupancyGrid room(100, 100, 0.05, {0.0, 0.0});
  for (int k = 0; k < 100; ++k)
    for (const CellIndex c : {CellIndex{k, 0}, CellIndex{k, 99}, CellIndex{0, k}, CellIndex{99, k}})
      room.set(c, OccupancyGrid::kOccupied);
  const RayCaster world(room);
  CarmenLog log;
  CarmenScan s;
  s.ranges.assign(181, 1.0f);
  s.angle_min = -M_PI / 2;
  s.angle_increment = M_PI / 180;
  s.pose = {2.5, 2.5, 0.3};
  log.scans = {s, s};
  log.scans[1].timestamp = 1.0;
  LogRenderOptions o;
  const double deg = M_PI / 180.0;
  // Beams spread evenly over the fov, even where a SICK's modes of 180 or 400 beams would not span
  // it; 270.004 degrees are 270 as PARAM reads them, and a whole turn has as many gaps as beams.
  for (const auto& [fov, beams, start, step] :
       {std::tuple{180.0, 181, -90.0, 1.0}, std::tuple{180.0, 180, -90.0, 180.0 / 179},
        std::tuple{180.0, 400, -90.0, 180.0 / 399}, std::tuple{270.004, 541, -135.0, 0.5},
        std::tuple{360.0, 720, -180.0, 0.5}}) {
    o.fov = fov * deg;
    o.beams = beams;
    const CarmenLog rendered = RenderLog(log, world, o);
    const CarmenLog read = ParseCarmenLog(FormatFlaserLog(rendered, "render"), "rendered");
    ASSERT_EQ(read.scans.size(), 2u);
    for (const CarmenLog* l : {&rendered, &read}) {
      EXPECT_NEAR(l->scans[1].angle_min, start * deg, 1e-9) << fov;
      EXPECT_NEAR(l->scans[1].angle_increment, step * deg, 1e-12) << fov;
      EXPECT_EQ(l->scans[1].ranges.size(), static_cast<size_t>(beams));
    }
  }
}

TEST(PathWalkers, WalkBackAndForthBesideThePathAtTheirPaceAndNeverOnTheScanner) {
  // An L: 10 m east, then 5 m north, over 30 s.
  std::vector<Pose2> path;
  std::vector<double> stamps;
  for (int k = 0; k <= 30; ++k) {
    const double along = 0.5 * k;
    path.push_back(along <= 10.0 ? Pose2{along, 0.0, 0.0} : Pose2{10.0, along - 10.0, M_PI / 2});
    stamps.push_back(k);
  }
  PathWalkerOptions o;
  o.count = 5;
  const PathWalkers walkers(path, stamps, o);
  EXPECT_NEAR(walkers.path_length(), 15.0, 1e-9);
  const Point2 far_away{100.0, 100.0};
  std::vector<Disc> before = walkers.At(0.0, far_away);
  ASSERT_EQ(before.size(), 5u);
  double moved = 0.0;
  for (double t = 0.25; t < 60.0; t += 0.25) {
    const std::vector<Disc> now = walkers.At(t, far_away);
    ASSERT_EQ(now.size(), 5u);
    for (size_t i = 0; i < now.size(); ++i) {
      const Point2 c = now[i].centre;
      EXPECT_DOUBLE_EQ(now[i].radius, o.radius);
      // Beside the path: within `side` of one of its legs, between its ends.
      const bool east = c.x() >= -1e-9 && c.x() <= 10.0 + 1e-9 && std::abs(c.y()) <= o.side + 1e-9;
      const bool north = c.y() >= -o.side && c.y() <= 5.0 + o.side && std::abs(c.x() - 10.0) <= o.side + 1e-9;
      EXPECT_TRUE(east || north) << c.transpose() << " at " << t;
      // At most 1.3 times the pace (a corner's cut is shorter still).
      EXPECT_LE((c - before[i].centre).norm(), 1.3 * o.speed * 0.25 + 2.0 * o.side + 1e-9);
      moved += (c - before[i].centre).norm();
    }
    before = now;
  }
  EXPECT_GT(moved / 5.0, 0.7 * o.speed * 60.0 * 0.8);  // they walk, at 0.7-1.3 m/s
  // Nobody stands on the scanner.
  for (double t = 0.0; t < 30.0; t += 0.5)
    for (const Disc& d : walkers.At(t, walkers.At(t, far_away)[2].centre)) EXPECT_NE(d.id, 2);
  o.radius = -1.0;
  EXPECT_THROW(PathWalkers(path, stamps, o), Error);
  EXPECT_THROW(PathWalkers(path, {0.0}, PathWalkerOptions{}), Error);
}

TEST(LogRenderer, PeopleWalkingThePathShortenBeamsTheMapWouldNot) {
  OccupancyGrid hall(400, 160, 0.05, {0.0, 0.0});
  hall.FillBox({0.0, 0.0}, {20.0, 0.1});
  hall.FillBox({0.0, 7.9}, {20.0, 8.0});
  hall.FillBox({0.0, 0.0}, {0.1, 8.0});
  hall.FillBox({19.9, 0.0}, {20.0, 8.0});
  const RayCaster world(hall);
  CarmenLog log;
  for (int k = 0; k <= 30; ++k) {
    CarmenScan s;
    s.ranges.assign(181, 1.0f);
    s.angle_min = -M_PI / 2;
    s.angle_increment = M_PI / 180;
    s.pose = {2.0 + 0.5 * k, 4.0, 0.0};
    s.timestamp = k;
    log.scans.push_back(s);
  }
  LogRenderOptions o;
  o.range_noise = 0.0;
  const CarmenLog empty = RenderLog(log, world, o);
  o.people.count = 6;
  const CarmenLog peopled = RenderLog(log, world, o);
  ASSERT_EQ(peopled.scans.size(), empty.scans.size());
  int shorter = 0, scans_with_people = 0;
  for (size_t k = 0; k < empty.scans.size(); ++k) {
    int here = 0;
    for (size_t i = 0; i < 181; ++i) {
      EXPECT_LE(peopled.scans[k].ranges[i], empty.scans[k].ranges[i] + 1e-6);
      if (peopled.scans[k].ranges[i] < empty.scans[k].ranges[i] - 0.05) ++here;
    }
    shorter += here;
    scans_with_people += here > 0;
  }
  EXPECT_GT(scans_with_people, 10);
  EXPECT_LT(shorter, 181 * 31 / 4);  // people, not walls
}

}  // namespace
}  // namespace navd::mapping
