// The command-line contract of navctl, navd and navsim, run as real processes: outputs, JSON,
// exit codes, one-line errors.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <memory>
#include <filesystem>
#include <fstream>
#include <optional>
#include <nlohmann/json.hpp>

#include "client_lib/telemetry.h"
#include "services/common/carmen_log.h"
#include "services/common/map_server_format.h"
#include "services/common/text_file.h"
#include "tests/support/navd_fixture.h"

namespace navd::testing {
namespace {

int Lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

TEST(Navctl, UnreachableServerIsOneLineAndNonZero) {
  // A port nobody listens on: bind-and-close is not needed; port 1 on loopback refuses.
  const auto r = RunCommand({NavctlBinary(), "--server", "127.0.0.1:1", "pose"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(Lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("cannot reach navd at 127.0.0.1:1"), std::string::npos) << r.output;
  const auto h = RunCommand({NavctlBinary(), "--server", "127.0.0.1:1", "health"});
  EXPECT_NE(h.exit_code, 0);
  EXPECT_EQ(Lines(h.output), 1) << h.output;
}

// Offline, `--json` gives the online plan's object. The crowd RRT rolled out along the street
// past two oncoming walkers ends in the goal's disc on its first pass: before its rounds knew the
// goal as an end, this trajectory swept past it and came back round (57 m for 38).
TEST(Navctl, OfflineCrowdRouteEndsAtTheGoalAsJson) {
  const auto r = RunCommand({NavctlBinary(), "plan",          "--map",    SourceDir() + "/worlds/street.yaml",
                             "--from",       "2,4",           "--to",     "40,4",
                             "--planner",    "kinodynamic",   "--option", "algorithm=3",
                             "--option",     "max_speed=1.5", "--option", "max_accel=1",
                             "--person",     "20,4.2,-1.3,0", "--person", "30,3,-1.2,0.1",
                             "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j["planner"], "kinodynamic");
  const auto& path = j["path"];
  ASSERT_GE(path.size(), 10u);
  const Point2 end(path.back()[0].get<double>(), path.back()[1].get<double>());
  EXPECT_LT(Distance(end, {40.0, 4.0}), 0.25 + 0.1) << end.transpose();  // the goal cell's centre, its disc
  EXPECT_LT(j["length"].get<double>(), 38.0 * 1.2);
}

TEST(Navctl, MalformedArgumentsAreRejectedLocally) {
  const auto r = RunCommand({NavctlBinary(), "plan", "--from", "1,abc", "--to", "2,2"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--from"), std::string::npos) << r.output;
}

TEST(Navctl, HealthPlanPoseNavigateAgainstRealDaemons) {
  NavdStack stack;
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  const std::string server = stack.address();

  auto health = RunCommand({NavctlBinary(), "--server", server, "health"});
  EXPECT_EQ(health.exit_code, 0) << health.output;
  EXPECT_NE(health.output.find("SERVING"), std::string::npos);

  auto plan = RunCommand({NavctlBinary(), "--server", server, "plan", "--from", "0.8,1", "--to", "3,2.6", "--json"});
  ASSERT_EQ(plan.exit_code, 0) << plan.output;
  const auto j = nlohmann::json::parse(plan.output);
  EXPECT_EQ(j["planner"], "astar");
  EXPECT_GT(j["length"].get<double>(), 2.5);
  EXPECT_GE(j["path"].size(), 2u);

  auto bad = RunCommand({NavctlBinary(), "--server", server, "plan", "--from", "0.8,1", "--to", "30,2"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_EQ(Lines(bad.output), 1) << bad.output;
  EXPECT_NE(bad.output.find("outside the map"), std::string::npos) << bad.output;

  auto unknown =
      RunCommand({NavctlBinary(), "--server", server, "plan", "--from", "0.8,1", "--to", "3,2.6", "--planner", "nope"});
  EXPECT_NE(unknown.exit_code, 0);
  EXPECT_NE(unknown.output.find("unknown planner 'nope'"), std::string::npos) << unknown.output;

  auto pose = RunCommand({NavctlBinary(), "--server", server, "pose", "--json"});
  ASSERT_EQ(pose.exit_code, 0) << pose.output;
  const auto p = nlohmann::json::parse(pose.output);
  EXPECT_NEAR(p["pose"]["x"].get<double>(), 0.8, 0.05);
  EXPECT_EQ(p["covariance"].size(), 9u);

  // Mapping while the robot drives: start, status, stop, save the built map.
  auto start =
      RunCommand({NavctlBinary(), "--server", server, "mapping", "start", "--mode", "known_poses", "--size", "12"});
  EXPECT_EQ(start.exit_code, 0) << start.output;
  EXPECT_NE(start.output.find("mapping active"), std::string::npos) << start.output;

  auto nav =
      RunCommand({NavctlBinary(), "--server", server, "navigate", "--to", "0.8,2.5,1.57", "--timeout", "60"}, 90.0);
  EXPECT_EQ(nav.exit_code, 0) << nav.output << stack.Logs();
  EXPECT_NE(nav.output.find("succeeded"), std::string::npos) << nav.output;
  auto mapping = RunCommand({NavctlBinary(), "--server", server, "mapping", "stop", "--json"});
  ASSERT_EQ(mapping.exit_code, 0) << mapping.output;
  const auto m = nlohmann::json::parse(mapping.output);
  EXPECT_FALSE(m["active"].get<bool>());
  EXPECT_GT(m["scans"].get<int>(), 5);
  EXPECT_EQ(m["width"].get<int>(), 240);
  const std::string saved = stack.dir() + "/mapped.yaml";
  auto save = RunCommand({NavctlBinary(), "--server", server, "save-map", saved, "--built"});
  EXPECT_EQ(save.exit_code, 0) << save.output;
  EXPECT_TRUE(std::filesystem::exists(stack.dir() + "/mapped.pgm")) << save.output;
  auto stop_again = RunCommand({NavctlBinary(), "--server", server, "mapping", "stop"});
  EXPECT_NE(stop_again.exit_code, 0);
  EXPECT_EQ(Lines(stop_again.output), 1) << stop_again.output;

  auto truth = RunCommand({NavctlBinary(), "truth", "--domain", std::to_string(stack.domain()), "--json"});
  ASSERT_EQ(truth.exit_code, 0) << truth.output;
  const auto t = nlohmann::json::parse(truth.output);
  EXPECT_NEAR(t["x"].get<double>(), 0.8, 0.25);
  EXPECT_NEAR(t["y"].get<double>(), 2.5, 0.25);
  EXPECT_EQ(t["collisions"].get<int>(), 0);

  // A navigation that cannot finish in time exits non-zero and leaves navd idle.
  auto timeout = RunCommand({NavctlBinary(), "--server", server, "navigate", "--to", "8.8,8.8", "--timeout", "0.5"});
  EXPECT_NE(timeout.exit_code, 0);
  EXPECT_NE(timeout.output.find("did not finish"), std::string::npos) << timeout.output;
  bool active = true;
  for (int i = 0; i < 100 && active; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    active = stack.client().GetStatus().active();
  }
  EXPECT_FALSE(active) << "navd kept the goal after navctl gave up";
}

// Eight FLASER scans turning on the spot at the centre of the square |x|, |y| <= 2 m, a quarter
// turn apart, written to `log`.
void WriteRoomScans(std::ostream& log) {
  for (int k = 0; k < 8; ++k) {
    const double heading = k * M_PI / 4;
    log << "FLASER 181";
    for (int i = 0; i <= 180; ++i) {
      // Distance from (0, 0) to the walls of the square along this beam.
      const double a = heading - M_PI / 2 + i * M_PI / 180;
      log << " " << 2.0 / std::max(std::abs(std::cos(a)), std::abs(std::sin(a)));
    }
    log << " 0 0 " << heading << " 0 0 " << heading << " " << k << " host " << k << "\n";
  }
}

// A command refused with one line that holds `line`, and `unwritten`, the file it was to write, not
// written.
void ExpectRefused(const std::vector<std::string>& command, const std::string& line,
                   const std::string& unwritten = "") {
  const auto r = RunCommand(command);
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_EQ(Lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find(line), std::string::npos) << r.output;
  if (!unwritten.empty()) EXPECT_FALSE(std::filesystem::exists(unwritten)) << unwritten;
}

// navd-replay builds a map from a CARMEN log's poses: a square room seen from its centre.
TEST(NavdReplay, BuildsAMapFromALogAndReportsBadLines) {
  const std::string dir = MakeTempDir();
  {
    std::ofstream log(dir + "/room.log");
    WriteRoomScans(log);
    log << "FLASER 2 1.0\n";  // malformed: line 9
  }
  const auto ok = RunCommand({NavdReplayBinary(), "--log", dir + "/room.log", "--out", dir + "/room.yaml"});
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("skipped 1 malformed"), std::string::npos) << ok.output;
  const OccupancyGrid map = LoadMapServerMap(dir + "/room.yaml");
  EXPECT_TRUE(map.IsOccupied(map.CellOf({2.02, 0.5})));
  EXPECT_EQ(map.at(map.CellOf({0.5, 0.5})), OccupancyGrid::kFree);

  const auto strict =
      RunCommand({NavdReplayBinary(), "--log", dir + "/room.log", "--out", dir + "/x.yaml", "--strict"});
  EXPECT_NE(strict.exit_code, 0);
  EXPECT_NE(strict.output.find("room.log:9"), std::string::npos) << strict.output;
  const auto missing = RunCommand({NavdReplayBinary(), "--log", dir + "/none.log", "--out", dir + "/x.yaml"});
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_EQ(Lines(missing.output), 1) << missing.output;
  // A pose graph is SLAM's: asked of the map mode, one line says so and nothing is written.
  const std::string room = dir + "/room.log";
  ExpectRefused({NavdReplayBinary(), "--log", room, "--out", dir + "/y.yaml", "--graph-out", dir + "/g.g2o"},
                "--graph-out is for --mode slam, not map", dir + "/y.yaml");
  EXPECT_FALSE(std::filesystem::exists(dir + "/g.g2o"));
  // So is every option another mode would ignore: the line names it and the modes it is for.
  ExpectRefused({NavdReplayBinary(), "--log", room, "--mode", "consistency", "--out", dir + "/z.txt", "--seed", "3"},
                "--seed is for --mode localize|slam|render, not consistency", dir + "/z.txt");
  ExpectRefused(
      {NavdReplayBinary(), "--log", room, "--mode", "slam", "--out", dir + "/z.tum", "--min-particles", "500"},
      "--min-particles is for --mode localize, not slam", dir + "/z.tum");
  // --pairing says how the log's own odometry meets the scans: with the noise protocol it would
  // change nothing.
  ExpectRefused({NavdReplayBinary(), "--log", room, "--mode", "slam", "--out", dir + "/z.tum", "--pairing", "stamp"},
                "--pairing is for --odometry log", dir + "/z.tum");
  ExpectRefused({NavctlBinary(), "replay", "--log", room, "--pairing", "stamp", "--server", ""},
                "--pairing is for --odometry log");
  // And every option its mode takes only beside another: SLAM's resolution is its map's, a map
  // given to the localiser has its own, and a log's own odometry draws no noise.
  ExpectRefused({NavdReplayBinary(), "--log", room, "--mode", "slam", "--out", dir + "/z.tum", "--resolution", "0.1"},
                "--resolution in --mode slam is the resolution of the map it writes", dir + "/z.tum");
  ExpectRefused({NavdReplayBinary(), "--log", room, "--mode", "localize", "--map", dir + "/room.yaml", "--resolution",
                 "0.1", "--out", dir + "/z.tum"},
                "--resolution is for the map drawn from the log's poses", dir + "/z.tum");
  ExpectRefused({NavdReplayBinary(), "--log", room, "--mode", "slam", "--odometry", "log", "--seed", "2", "--out",
                 dir + "/z.tum"},
                "--seed with --odometry log is for --mode localize --localizer amcl", dir + "/z.tum");
  ExpectRefused({NavdReplayBinary(), "--log", room, "--mode", "localize", "--odometry", "log", "--localizer", "ekf",
                 "--seed", "2", "--out", dir + "/z.tum"},
                "--seed with --odometry log is for --mode localize --localizer amcl", dir + "/z.tum");
  // Beside what they need, they run.
  const auto resolved = RunCommand({NavdReplayBinary(), "--log", room, "--mode", "slam", "--out", dir + "/z.tum",
                                    "--resolution", "0.1", "--map-out", dir + "/z.yaml"});
  ASSERT_EQ(resolved.exit_code, 0) << resolved.output;
  EXPECT_NEAR(LoadMapServerMap(dir + "/z.yaml").resolution(), 0.1, 1e-9);
}

// A log spread wider than a grid holds at 5 cm (two rooms 250 m apart, as a campus's buildings):
// the map is drawn at the finest resolution that fits, says so, and holds both rooms' walls.
TEST(NavdReplay, MapsALogSpreadWiderThanAGridHoldsAtACoarserResolution) {
  const std::string dir = MakeTempDir();
  {
    std::ofstream log(dir + "/campus.log");
    for (const double c : {0.0, 250.0}) {
      log << "FLASER 181";
      for (int i = 0; i <= 180; ++i) {
        const double a = -M_PI / 2 + i * M_PI / 180;
        log << " " << 2.0 / std::max(std::abs(std::cos(a)), std::abs(std::sin(a)));
      }
      log << " " << c << " " << c << " 0 " << c << " " << c << " 0 " << c << " host " << c << "\n";
    }
  }
  const auto ok = RunCommand({NavdReplayBinary(), "--log", dir + "/campus.log", "--out", dir + "/campus.yaml"});
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("drawn at 0.055 m, not 0.050"), std::string::npos) << ok.output;
  const OccupancyGrid map = LoadMapServerMap(dir + "/campus.yaml");
  EXPECT_NEAR(map.resolution(), 0.055, 1e-9);
  EXPECT_LE(static_cast<long long>(map.width()) * map.height(), OccupancyGrid::kMaxCells);
  for (const double c : {0.0, 250.0}) {
    EXPECT_TRUE(map.IsOccupied(map.CellOf({c + 2.02, c}))) << c;
    EXPECT_EQ(map.at(map.CellOf({c + 0.5, c})), OccupancyGrid::kFree) << c;
  }
}

// A raw robot log: no corrected poses, odometry in ODOM lines, stamps that repeat. SLAM runs on
// the log's own odometry and writes one TUM line per FLASER line, in file order. Bad --odometry,
// --pairing and --min-particles values are refused, naming the flag, and nothing is written.
TEST(NavdReplay, SlamRunsOnARawLogsOwnOdometryWithOneTumLinePerScan) {
  const std::string dir = MakeTempDir();
  {
    std::ofstream log(dir + "/raw.log");
    for (int k = 0; k < 12; ++k) {
      const double heading = k * M_PI / 6, stamp = 100.0 + std::floor(k / 4.0);  // four scans share each stamp
      log << "ODOM 0 0 " << heading << " 0 0 0 " << stamp << " host " << stamp << "\n";
      log << "FLASER 181";
      for (int i = 0; i <= 180; ++i) {
        const double a = heading - M_PI / 2 + i * M_PI / 180;
        log << " " << 2.0 / std::max(std::abs(std::cos(a)), std::abs(std::sin(a)));
      }
      log << " 9 9 0 9 9 0 " << stamp << " host " << stamp << "\n";  // pose fields say nothing true here
    }
  }
  const auto r = RunCommand({NavdReplayBinary(), "--log", dir + "/raw.log", "--mode", "slam", "--odometry", "log",
                             "--out", dir + "/raw.tum"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream tum(dir + "/raw.tum");
  std::vector<double> headings;
  double x0 = 0, y0 = 0;
  for (std::string line; std::getline(tum, line);) {
    double t, x, y, z, qx, qy, qz, qw;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf %lf %lf %lf %lf %lf %lf %lf", &t, &x, &y, &z, &qx, &qy, &qz, &qw), 8)
        << line;
    if (headings.empty()) x0 = x, y0 = y;
    EXPECT_NEAR(std::hypot(x - x0, y - y0), 0.0, 0.05) << line;  // turning on the spot, as the ODOM lines say
    headings.push_back(2 * std::atan2(qz, qw));
  }
  ASSERT_EQ(headings.size(), 12u);
  for (size_t k = 1; k < headings.size(); ++k)
    EXPECT_NEAR(NormalizeAngle(headings[k] - headings[k - 1]), M_PI / 6, 0.05) << "scan " << k;
  const auto bad = RunCommand({NavdReplayBinary(), "--log", dir + "/raw.log", "--mode", "slam", "--odometry", "wheels",
                               "--out", dir + "/x.tum"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("--odometry"), std::string::npos) << bad.output;
  for (const char* pairing : {"later", "1.5", "-0.1", "nan", "inf", " 0.5"}) {
    const auto refused = RunCommand({NavdReplayBinary(), "--log", dir + "/raw.log", "--mode", "slam", "--odometry",
                                     "log", "--pairing", pairing, "--out", dir + "/x.tum"});
    EXPECT_NE(refused.exit_code, 0) << pairing;
    EXPECT_NE(refused.output.find("--pairing"), std::string::npos) << refused.output;
    EXPECT_FALSE(std::filesystem::exists(dir + "/x.tum"));
  }
  for (const char* count : {"5", "many", "1e9"}) {
    const auto refused = RunCommand({NavdReplayBinary(), "--log", dir + "/raw.log", "--mode", "localize", "--odometry",
                                     "log", "--min-particles", count, "--out", dir + "/x.tum"});
    EXPECT_NE(refused.exit_code, 0) << count;
    EXPECT_NE(refused.output.find("--min-particles"), std::string::npos) << refused.output;
    EXPECT_FALSE(std::filesystem::exists(dir + "/x.tum"));
  }
}

// A log rendered again (navd-replay --mode render) holds the log's poses with scans cast in the map
// those poses draw; with --step, more scans between them. The room log of the map test: eight
// scans turning on the spot in a 4 m square.
// The range (m) from (x, y) along `bearing` (rad) to the walls of the room [0, width] x [0, height].
double RangeInRoom(double width, double height, double x, double y, double bearing) {
  const double c = std::cos(bearing), s = std::sin(bearing);
  const double tx = c > 1e-9 ? (width - x) / c : c < -1e-9 ? -x / c : 1e9;
  const double ty = s > 1e-9 ? (height - y) / s : s < -1e-9 ? -y / s : 1e9;
  return std::min(tx, ty);
}

// A log of RAWLASER1 and ODOM lines only (logged without the robot's laser messages): the scans,
// a full turn of 1-degree beams as their lines say, are placed by the odometry at their stamps,
// and SLAM takes their own geometry. The ODOM lines overstate each 0.1 m step by 15 %: the scans
// of the room's walls hold the chain to the true 1.9 m (read as 180-degree scans, they would not).
TEST(NavdReplay, SlamRunsOnALogOfRawLaserScansPlacedByItsOdometry) {
  const std::string dir = MakeTempDir();
  const double width = 8.0, height = 5.0, step = 0.1, stated = 0.115;
  {
    std::ofstream log(dir + "/rawlaser.log");
    for (int k = 0; k < 20; ++k) {
      const double x = 2.0 + k * step, y = 2.3;
      log << "ODOM " << 2.0 + k * stated << " " << y << " 0 0 0 0 " << 100.0 + k << " host " << 100.0 + k << "\n";
      log << "RAWLASER1 0 " << -M_PI << " " << 2 * M_PI << " " << M_PI / 180 << " 30 0.01 0 360";
      for (int i = 0; i < 360; ++i) log << " " << RangeInRoom(width, height, x, y, -M_PI + i * M_PI / 180);
      log << " 0 " << 100.0 + k << " host " << 100.0 + k << "\n";  // at its ODOM line's stamp
    }
  }
  const auto r = RunCommand({NavdReplayBinary(), "--log", dir + "/rawlaser.log", "--mode", "slam", "--odometry", "log",
                             "--out", dir + "/rawlaser.tum"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream tum(dir + "/rawlaser.tum");
  std::vector<std::array<double, 2>> positions;
  for (std::string line; std::getline(tum, line);) {
    double t, x, y;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf %lf %lf", &t, &x, &y), 3) << line;
    positions.push_back({x, y});
  }
  ASSERT_EQ(positions.size(), 20u);
  EXPECT_NEAR(positions.front()[0], 2.0, 1e-6);  // the first scan where the odometry put it
  EXPECT_NEAR(positions.back()[0] - positions.front()[0], 19 * step, 0.05) << "odometry alone: " << 19 * stated;
  EXPECT_NEAR(positions.back()[1] - positions.front()[1], 0.0, 0.05);
}

TEST(NavdReplay, RenderWritesALogWhoseScansAreCastInTheMapOfItsPoses) {
  const std::string dir = MakeTempDir();
  {
    std::ofstream log(dir + "/room.log");
    WriteRoomScans(log);
  }
  const auto r = RunCommand({NavdReplayBinary(), "--log", dir + "/room.log", "--mode", "render", "--range-noise", "0",
                             "--out", dir + "/rendered.log"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const CarmenLog source = ReadCarmenLog(dir + "/room.log", true);
  const CarmenLog rendered = ReadCarmenLog(dir + "/rendered.log", true);
  ASSERT_EQ(rendered.scans.size(), source.scans.size());
  for (size_t k = 0; k < rendered.scans.size(); ++k) {
    EXPECT_NEAR(rendered.scans[k].pose.theta, source.scans[k].pose.theta, 1e-6);
    ASSERT_EQ(rendered.scans[k].ranges.size(), 181u);
    // The walls are cells of the 5 cm map drawn from these very scans: within a cell and a half.
    for (size_t i = 0; i < 181; ++i)
      EXPECT_NEAR(rendered.scans[k].ranges[i], source.scans[k].ranges[i], 0.075) << "scan " << k << " beam " << i;
  }
  const auto dense = RunCommand({NavdReplayBinary(), "--log", dir + "/room.log", "--mode", "render", "--step", "0.1",
                                 "--turn", "0.1", "--out", dir + "/dense.log"});
  ASSERT_EQ(dense.exit_code, 0) << dense.output;
  EXPECT_EQ(ReadCarmenLog(dir + "/dense.log", true).scans.size(), 7u * 8u + 1u);  // pi/4 in 0.1 rad turns
  const auto bad = RunCommand(
      {NavdReplayBinary(), "--log", dir + "/room.log", "--mode", "render", "--step", "-1", "--out", dir + "/x.log"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("--step"), std::string::npos) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.log"));
}

// Rendered by another scanner (--fov, --beams), a log says its beams in its front laser's PARAM
// lines, and what reads it places them there: the room's walls where a 270-degree scanner's 541
// beams meet them. On the first 300 scans of the Intel log rendered so, SLAM holds within 3 cm;
// the same FLASER lines without those PARAM lines read as a 180-degree SICK's and SLAM fails.
TEST(NavdReplay, RendersAnotherScannerWhoseBeamsTheLogsParamLinesPlace) {
  const std::string dir = MakeTempDir();
  {
    std::ofstream log(dir + "/room.log");
    WriteRoomScans(log);
  }
  const auto r = RunCommand({NavdReplayBinary(), "--log", dir + "/room.log", "--mode", "render", "--range-noise", "0",
                             "--fov", "270", "--beams", "541", "--out", dir + "/wide.log"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const CarmenLog wide = ReadCarmenLog(dir + "/wide.log", true);
  ASSERT_EQ(wide.scans.size(), 8u);
  for (size_t k = 0; k < wide.scans.size(); ++k) {
    const CarmenScan& s = wide.scans[k];
    ASSERT_EQ(s.ranges.size(), 541u);
    EXPECT_NEAR(s.angle_min, -135 * M_PI / 180, 1e-9);
    EXPECT_NEAR(s.angle_increment, 0.5 * M_PI / 180, 1e-9);
    for (size_t i = 0; i < s.ranges.size(); ++i)
      EXPECT_NEAR(s.ranges[i], RangeInRoom(4.0, 4.0, 2.0, 2.0, s.pose.theta + s.angle_min + i * s.angle_increment),
                  0.075)
          << "scan " << k << " beam " << i;
  }
  const auto half = RunCommand(
      {NavdReplayBinary(), "--log", dir + "/room.log", "--mode", "render", "--fov", "270", "--out", dir + "/x.log"});
  EXPECT_NE(half.exit_code, 0);
  EXPECT_NE(half.output.find("--beams"), std::string::npos) << half.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.log"));

  const std::string intel = SourceDir() + "/../shared/data/carmen/intel-corrected.log.gz";
  if (!std::filesystem::exists(intel)) GTEST_SKIP() << "shared data not beside the checkout: " << intel;
  ASSERT_EQ(RunCommand({NavdReplayBinary(), "--log", intel, "--mode", "render", "--fov", "270", "--beams", "541",
                        "--out", dir + "/intel-wide.log"})
                .exit_code,
            0);
  {
    std::ifstream in(dir + "/intel-wide.log");
    std::ofstream with(dir + "/with.log"), without(dir + "/without.log");
    int scans = 0;
    for (std::string line; std::getline(in, line) && scans < 300;) {
      with << line << "\n";
      if (line.rfind("PARAM", 0) == 0) continue;
      without << line << "\n";
      ++scans;
    }
  }
  auto slam_ate = [&](const std::string& log) {
    const auto run =
        RunCommand({NavdReplayBinary(), "--log", log, "--mode", "slam", "--seed", "2", "--out", dir + "/x.tum"}, 120.0);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    const size_t at = run.output.find("ATE RMSE ");
    double ate = 1e9;
    if (at != std::string::npos) std::sscanf(run.output.c_str() + at, "ATE RMSE %lf", &ate);
    return ate;
  };
  const double placed = slam_ate(dir + "/with.log"), guessed = slam_ate(dir + "/without.log");
  std::printf("Intel's first 300 scans by a 270-degree scanner: SLAM ATE %.4f m, read as 180 degrees %.4f m\n", placed,
              guessed);
  EXPECT_LE(placed, 0.03);
  EXPECT_GE(guessed, 0.3);
}

// scripts/realdata, the evaluation over real logs, on CI's bounded subset: two logs, one seed,
// offline (SLAM, localisation) and online (the log over DDS to a running navd). Thresholds guard
// against regressions of the figures in docs/results.md; a wrong loop closure or an offline loss
// fails. navd declaring the pose lost online is reported, not failed: it still happens on Intel
// under load. Online runs at 25x here: beside the rest of the suite on 2 cores, navd at 50x can fall
// far enough behind the replay to lose the Intel pose for good.
TEST(Realdata, TwoLogsOneSeedOfflineAndOnlineWithinTheirThresholds) {
  const std::string data = SourceDir() + "/../shared/data/carmen";
  if (!std::filesystem::exists(data + "/intel-corrected.log.gz")) GTEST_SKIP() << "shared data not beside the checkout";
  const std::string dir = MakeTempDir();
  const std::string replay = NavdReplayBinary();
  const std::string build_dir = replay.substr(0, replay.rfind("/tools/"));
  const auto r = RunCommand({"/usr/bin/env",
                             "NAVD_REALDATA_DOMAIN=" + std::to_string(ReserveDomain()),
                             "NAVD_BUILD_DIR=" + build_dir,
                             SourceDir() + "/scripts/realdata",
                             data,
                             "--logs",
                             "intel,freiburg-101",
                             "--seeds",
                             "1-1",
                             "--online",
                             "--online-rate",
                             "25",
                             "--jobs",
                             "1",
                             "--out",
                             dir,
                             "--max-slam-ate",
                             "0.10",
                             "--max-localize-rmse",
                             "0.06",
                             "--max-online-rmse",
                             "0.15"},
                            280.0);
  std::printf("%s\n",
              r.output.substr(r.output.find("\nlog ") == std::string::npos ? 0 : r.output.find("\nlog ")).c_str());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("intel-corrected             910 |"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("freiburg-101-corrected      292 |"), std::string::npos) << r.output;
}

// Real laser data: the Intel Research Lab log in ../shared/data (present wherever CI runs). The
// map is built from the log's corrected poses; the odometry is corrupted (5%, 2 deg/m, seeded).
// The particle filter, seed 002's EKF and seed 000's odometric calibration all localise on it.
class NavdReplayLocalisation : public ::testing::TestWithParam<std::string> {};

TEST_P(NavdReplayLocalisation, LocalisesOnTheIntelLog) {
  const std::string log = SourceDir() + "/../shared/data/carmen/intel-corrected.log.gz";
  if (!std::filesystem::exists(log)) GTEST_SKIP() << "shared data not beside the checkout: " << log;
  const std::string dir = MakeTempDir();
  const auto r = RunCommand(
      {NavdReplayBinary(), "--log", log, "--mode", "localize", "--localizer", GetParam(), "--out", dir + "/est.tum"},
      120.0);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  double rmse = -1, heading = -1;
  const size_t at = r.output.find("position RMSE ");
  ASSERT_NE(at, std::string::npos) << r.output;
  ASSERT_EQ(std::sscanf(r.output.c_str() + at, "position RMSE %lf m, heading RMSE %lf rad", &rmse, &heading), 2);
  std::printf("Intel log, %s: position RMSE %.4f m, heading RMSE %.4f rad\n", GetParam().c_str(), rmse, heading);
  EXPECT_LE(rmse, GetParam() == "ekf" ? 0.045 : 0.055);
  EXPECT_LE(heading, 0.02);
  EXPECT_NE(r.output.find("never lost"), std::string::npos) << r.output;
  // One TUM line per scan.
  std::ifstream tum(dir + "/est.tum");
  int lines = 0;
  for (std::string line; std::getline(tum, line);) ++lines;
  EXPECT_EQ(lines, 910);
}
INSTANTIATE_TEST_SUITE_P(Localisers, NavdReplayLocalisation, ::testing::Values("amcl", "ekf", "calibration"),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

// A folder of logs where one cannot be read: its row says why, the others are still run, and with
// a threshold the whole run fails.
TEST(Realdata, ALogThatCannotBeReadGetsAFailedRowAndTheOthersTheirs) {
  const std::string dir = MakeTempDir(), logs = dir + "/logs";
  std::filesystem::create_directories(logs);
  std::ofstream(logs + "/broken.log") << "ODOM 0 0 0 0 0 0 1 h 1\n";
  {
    std::ofstream log(logs + "/room.log");
    for (int k = 0; k < 30; ++k) {
      const double x = 2.0 + 0.1 * k, y = 2.3, stamp = 100.0 + k;
      log << "FLASER 181";
      for (int i = 0; i <= 180; ++i) log << " " << RangeInRoom(8.0, 5.0, x, y, -M_PI / 2 + i * M_PI / 180);
      log << " " << x << " " << y << " 0 " << x << " " << y << " 0 " << stamp << " host " << stamp << "\n";
    }
  }
  const std::string replay = NavdReplayBinary();
  const std::string build_dir = replay.substr(0, replay.rfind("/tools/"));
  auto run = [&](std::vector<std::string> more) {
    std::vector<std::string> command{"/usr/bin/env",
                                     "NAVD_BUILD_DIR=" + build_dir,
                                     SourceDir() + "/scripts/realdata",
                                     logs,
                                     "--seeds",
                                     "1-1",
                                     "--jobs",
                                     "1",
                                     "--out",
                                     dir + "/out"};
    command.insert(command.end(), more.begin(), more.end());
    return RunCommand(command, 120.0);
  };
  const auto r = run({});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("broken                   failed: navd-replay: " + logs + "/broken.log: no FLASER"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("room                         30 |"), std::string::npos) << r.output;
  const auto gated = run({"--max-slam-ate", "1.0", "--markdown"});
  EXPECT_NE(gated.exit_code, 0) << gated.output;
  EXPECT_NE(gated.output.find("| broken | failed: "), std::string::npos) << gated.output;
  EXPECT_NE(gated.output.find("| room | 30 | "), std::string::npos) << gated.output;
}

// Scan k of a drive through a 10 x 6 m room (walls at x = +-5, y = +-3): where it was taken.
std::array<double, 3> RoomDrivePose(int k) {
  return {-4.0 + 0.2 * k, 0.3 * std::sin(0.3 * k), 0.2 * std::sin(0.2 * k)};
}

// A FLASER line of that room seen from (x, y, theta), stamped t, whose pose fields say `logged`.
std::string RoomFlaserLine(const std::array<double, 3>& seen_from, const std::array<double, 3>& logged, double t) {
  const auto& [x, y, theta] = seen_from;
  std::ostringstream line;
  line << "FLASER 181";
  for (int i = 0; i <= 180; ++i)
    line << " " << RangeInRoom(10.0, 6.0, x + 5.0, y + 3.0, theta - M_PI / 2 + i * M_PI / 180);
  for (int twice = 0; twice < 2; ++twice) line << " " << logged[0] << " " << logged[1] << " " << logged[2];
  line << " " << t << " host " << t << "\n";
  return line.str();
}

// navd-replay --mode consistency judges a trajectory by its own scans: in a 10 x 6 m room, the
// scans placed at the poses they were taken from agree better than at poses that drift as SLAM's
// might (2 mrad of heading and 1 cm sideways more per scan).
TEST(ScanConsistency, ADriftingTrajectoryReadsWorseThanTheTrueOne) {
  const std::string dir = MakeTempDir();
  auto tum_line = [](double t, double x, double y, double theta) {
    char line[160];
    std::snprintf(line, sizeof(line), "%.3f %.6f %.6f 0 0 0 %.9f %.9f\n", t, x, y, std::sin(theta / 2),
                  std::cos(theta / 2));
    return std::string(line);
  };
  {
    std::ofstream log(dir + "/room.log"), exact(dir + "/exact.tum"), drift(dir + "/drift.tum");
    exact << "# t x y z qx qy qz qw\n";
    for (int k = 0; k < 40; ++k) {
      const auto pose = RoomDrivePose(k);
      const auto& [x, y, theta] = pose;
      const double t = 100.0 + k;
      log << RoomFlaserLine(pose, pose, t);
      exact << tum_line(t, x, y, theta);
      drift << tum_line(t, x, y + 0.01 * k, theta + 0.002 * k);
    }
  }
  // The mean distance (mm) it prints, and the returns scored.
  auto judge = [&](const std::string& trajectory) {
    std::vector<std::string> args{NavdReplayBinary(), "--log", dir + "/room.log", "--mode",
                                  "consistency",      "--out", dir + "/scans.txt"};
    if (!trajectory.empty()) args.insert(args.end(), {"--trajectory", trajectory});
    const auto r = RunCommand(args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    long long scored = 0;
    double mm = -1.0;
    const size_t at = r.output.find("returns scored");
    EXPECT_NE(at, std::string::npos) << r.output;
    if (at != std::string::npos)
      std::sscanf(r.output.c_str() + r.output.rfind(", ", at - 1) + 2, "%lld returns scored, %lf mm", &scored, &mm);
    return std::make_pair(mm, scored);
  };
  const auto log_poses = judge(""), exact = judge(dir + "/exact.tum"), drift = judge(dir + "/drift.tum");
  EXPECT_EQ(exact, log_poses);  // the same poses, read from the TUM file
  EXPECT_GT(exact.second, 1000);
  EXPECT_LT(exact.first, 5.0);
  EXPECT_GT(drift.first, 2.0 * exact.first + 5.0);
  // Per scan, one line each after the header.
  std::ifstream scans(dir + "/scans.txt");
  int lines = 0;
  for (std::string line; std::getline(scans, line);) lines += line.empty() || line[0] == '#' ? 0 : 1;
  EXPECT_EQ(lines, 40);

  const auto not_tum = RunCommand({NavdReplayBinary(), "--log", dir + "/room.log", "--mode", "consistency",
                                   "--trajectory", dir + "/room.log", "--out", dir + "/x.txt"});
  EXPECT_NE(not_tum.exit_code, 0);
  EXPECT_NE(not_tum.output.find("navd-replay: " + dir + "/room.log:1: not a TUM pose"), std::string::npos)
      << not_tum.output;
  {
    std::ofstream short_tum(dir + "/short.tum");
    short_tum << tum_line(100.0, 0.0, 0.0, 0.0);
  }
  const auto too_short = RunCommand({NavdReplayBinary(), "--log", dir + "/room.log", "--mode", "consistency",
                                     "--trajectory", dir + "/short.tum", "--out", dir + "/x.txt"});
  EXPECT_NE(too_short.exit_code, 0);
  EXPECT_NE(too_short.output.find("--trajectory: 1 poses for the log's 40 scans"), std::string::npos)
      << too_short.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.txt"));
}

// A log whose scan 20 says a pose 0.1 m and 0.1 rad off where it was taken: --scan 20 finds the
// pose the other scans place it at, and --scan 10 that its own is where they place it.
TEST(ScanConsistency, FindsWhereTheOtherScansPlaceAScanWhoseLoggedPoseIsOff) {
  const std::string dir = MakeTempDir();
  {
    std::ofstream log(dir + "/room.log");
    for (int k = 0; k < 40; ++k) {
      auto logged = RoomDrivePose(k);
      if (k == 20) logged = {logged[0] + 0.1, logged[1], logged[2] + 0.1};
      log << RoomFlaserLine(RoomDrivePose(k), logged, 100.0 + k);
    }
  }
  auto fit = [&](const std::string& scan) {
    const auto r = RunCommand({NavdReplayBinary(), "--log", dir + "/room.log", "--mode", "consistency", "--scan", scan,
                               "--out", dir + "/scan.txt"});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    std::array<double, 5> read{};  // at the log's pose, at the best (mm); the best's offset x, y, theta
    const size_t at = r.output.find("scan " + scan + " at");
    EXPECT_NE(at, std::string::npos) << r.output;
    if (at != std::string::npos) {
      EXPECT_EQ(
          std::sscanf(r.output.c_str() + at,
                      "scan %*d at the log's poses: %lf mm from the other scans' lines, %lf mm at its best, %lf m, "
                      "%lf m, %lf rad",
                      &read[0], &read[1], &read[2], &read[3], &read[4]),
          5)
          << r.output;
    }
    return read;
  };
  const auto off = fit("20");
  EXPECT_GT(off[0], 3.0 * off[1]);
  EXPECT_NEAR(off[2], -0.1, 0.051);
  EXPECT_NEAR(off[3], 0.0, 0.051);
  EXPECT_NEAR(off[4], -0.1, 0.021);
  const auto right = fit("10");
  EXPECT_EQ(right[0], right[1]);
  EXPECT_EQ(right[4], 0.0);
  const auto refused = RunCommand({NavdReplayBinary(), "--log", dir + "/room.log", "--mode", "consistency", "--scan",
                                   "40", "--out", dir + "/x.txt"});
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_NE(refused.output.find("navd-replay: --scan: the log has scans 0 to 39, not 40"), std::string::npos)
      << refused.output;
}

// navd-replay --mode slam on a real log of ../shared/data: its ATE, loop closures and wrong ones.
struct SlamRun {
  double ate = -1.0;
  double step_error = -1.0;  // m, mean relative error per scan step
  int closures = -1, wrong = -1;
  double closure_median = -1.0;  // m off the corrected poses; -1 without closures
  std::string output;
};

// seed: of the noise protocol's odometry; none for a log's own (--odometry log in `more`).
SlamRun RunSlam(const std::string& log, std::optional<int> seed, const std::string& dir,
                const std::vector<std::string>& more = {}) {
  SlamRun out;
  std::vector<std::string> command{
      NavdReplayBinary(), "--log", log, "--mode", "slam", "--out", dir + "/est.tum", "--map-out", dir + "/map.yaml"};
  if (seed) command.insert(command.end(), {"--seed", std::to_string(*seed)});
  command.insert(command.end(), more.begin(), more.end());
  const auto r = RunCommand(command, 180.0);
  out.output = r.output;
  const size_t at = r.output.find("slam: ");
  if (r.exit_code != 0 || at == std::string::npos) return out;
  const size_t loops = r.output.find(" loop closures (", at), rmse = r.output.find("ATE RMSE ", at);
  if (loops == std::string::npos || rmse == std::string::npos) return out;
  const size_t start = r.output.rfind(", ", loops);
  if (std::sscanf(r.output.c_str() + start, ", %d loop closures (%d wrong)", &out.closures, &out.wrong) != 2 ||
      std::sscanf(r.output.c_str() + rmse, "ATE RMSE %lf", &out.ate) != 1)
    out.ate = -1.0;
  const size_t step = r.output.find("relative error per scan step ", at);
  if (step != std::string::npos)
    std::sscanf(r.output.c_str() + step, "relative error per scan step %lf", &out.step_error);
  const size_t offsets = r.output.find("loop closures off the corrected poses: ", at);
  if (offsets != std::string::npos)
    std::sscanf(r.output.c_str() + offsets, "loop closures off the corrected poses: median %lf", &out.closure_median);
  return out;
}

// Graph SLAM on the Intel log with corrupted odometry (5%, 2 deg/m, seed 3): the trajectory of
// every scan within 0.10 m RMSE of the corrected poses after SE(2) alignment, loops closed, none of
// them wrong (each judged against the corrected poses), the map written as map_server YAML + PGM
// and the pose graph in g2o's format, its vertices where the trajectory puts their scans.
TEST(NavdReplay, SlamOnTheIntelLogClosesLoopsAndStaysWithinTenCentimetres) {
  const std::string log = SourceDir() + "/../shared/data/carmen/intel-corrected.log.gz";
  if (!std::filesystem::exists(log)) GTEST_SKIP() << "shared data not beside the checkout: " << log;
  const std::string dir = MakeTempDir();
  const SlamRun run = RunSlam(log, 3, dir, {"--graph-out", dir + "/graph.g2o"});
  ASSERT_GE(run.ate, 0.0) << run.output;
  std::printf(
      "Intel log, slam: ATE RMSE %.4f m, relative error per step %.4f m, %d loop closures (median %.3f m off the "
      "corrected poses), %d wrong\n",
      run.ate, run.step_error, run.closures, run.closure_median, run.wrong);
  EXPECT_LE(run.ate, 0.10);
  // Seeds 1-5 read 0.0237 m or so, from perfect odometry 0.0232: the scans' own disagreement with
  // the corrected poses, step by step.
  EXPECT_GT(run.step_error, 0.0) << run.output;
  EXPECT_LE(run.step_error, 0.03);
  EXPECT_GE(run.closures, 1);
  EXPECT_EQ(run.wrong, 0) << run.output;
  // Seeds 1-5 read about 0.025 m: where the scans and the corrected poses part on two passes.
  EXPECT_GT(run.closure_median, 0.0) << run.output;
  EXPECT_LE(run.closure_median, 0.05) << run.output;
  std::vector<std::array<double, 3>> trajectory;
  std::ifstream tum(dir + "/est.tum");
  for (std::string line; std::getline(tum, line);) {
    double t, x, y, z, qx, qy, qz, qw;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf %lf %lf %lf %lf %lf %lf %lf", &t, &x, &y, &z, &qx, &qy, &qz, &qw), 8);
    trajectory.push_back({x, y, 2.0 * std::atan2(qz, qw)});
  }
  EXPECT_EQ(trajectory.size(), 910u);
  EXPECT_TRUE(std::filesystem::exists(dir + "/map.pgm"));

  std::ifstream g2o(dir + "/graph.g2o");
  std::set<int> vertices;
  int edges = 0;
  for (std::string line; std::getline(g2o, line);) {
    char tag[16];
    if (line.rfind("VERTEX_SE2 ", 0) == 0) {
      int id;
      double x, y, theta;
      ASSERT_EQ(std::sscanf(line.c_str(), "%15s %d %lf %lf %lf", tag, &id, &x, &y, &theta), 5) << line;
      ASSERT_TRUE(id >= 0 && id < static_cast<int>(trajectory.size())) << line;
      EXPECT_NEAR(x, trajectory[id][0], 1e-5) << line;
      EXPECT_NEAR(y, trajectory[id][1], 1e-5) << line;
      EXPECT_NEAR(std::remainder(theta - trajectory[id][2], 2.0 * M_PI), 0.0, 1e-5) << line;
      vertices.insert(id);
    } else {
      int from, to;
      double m[3], info[6];
      ASSERT_EQ(std::sscanf(line.c_str(), "%15s %d %d %lf %lf %lf %lf %lf %lf %lf %lf %lf", tag, &from, &to, &m[0],
                            &m[1], &m[2], &info[0], &info[1], &info[2], &info[3], &info[4], &info[5]),
                12)
          << line;
      EXPECT_STREQ(tag, "EDGE_SE2");
      EXPECT_TRUE(vertices.count(from) && vertices.count(to)) << line;
      EXPECT_GT(info[0], 0.0) << line;
      EXPECT_GT(info[3], 0.0) << line;
      EXPECT_GT(info[5], 0.0) << line;
      ++edges;
    }
  }
  EXPECT_EQ(vertices.count(0), 1u);
  // A chain through every node, and the loop closures and refinement matches on top.
  EXPECT_GE(edges, static_cast<int>(vertices.size()) - 1 + run.closures);
  EXPECT_NE(run.output.find("pose graph: " + std::to_string(vertices.size()) + " nodes"), std::string::npos)
      << run.output;
}

// The aces log's scans are stamped like the ODOM line before them but move with the lines after
// them: paired by stamp, its own odometry turns 0.1-0.4 rad more or less than the robot did
// between some scans. navd-replay pairs the lines as the scans agree, and the chain holds on the
// odometry alone, without the front end's wider search or the odometry's error learnt. At scan 104
// the paired odometry still errs by about 0.23 rad, at the edge of the front end's window: a
// prediction moved there by a learnt turn error falls beyond it, and the wider search (on by
// default with --odometry log) brings it back.
TEST(NavdReplay, SlamOnTheAcesLogsOwnOdometryPairsItsOdomLinesAsItsScansAgree) {
  const std::string log = SourceDir() + "/../shared/data/carmen/aces-corrected.log.gz";
  if (!std::filesystem::exists(log)) GTEST_SKIP() << "shared data not beside the checkout: " << log;
  const SlamRun run = RunSlam(log, std::nullopt, MakeTempDir(),
                              {"--odometry", "log", "--front-recovery", "0", "--odometry-bias", "off"});
  ASSERT_GE(run.ate, 0.0) << run.output;
  std::printf("aces log, own odometry, no recovery: ATE RMSE %.4f m\n", run.ate);
  EXPECT_NE(run.output.find("ODOM lines paired at"), std::string::npos) << run.output;
  EXPECT_LE(run.ate, 0.15);
  EXPECT_EQ(run.wrong, 0) << run.output;
}

// The csail log's stamps cannot time anything, and however its ODOM lines are paired, its own
// odometry turns 0.2-0.4 rad more or less than the robot did between a tenth of its scans,
// beyond the front end's window: searched again wider where a scan fits poorly (on by default
// with --odometry log), the chain holds; without, it breaks and ends metres off.
TEST(NavdReplay, SlamOnTheCsailLogsOwnOdometrySearchesAgainWhereItsHeadingJumps) {
  const std::string log = SourceDir() + "/../shared/data/carmen/csail-corrected.log.gz";
  if (!std::filesystem::exists(log)) GTEST_SKIP() << "shared data not beside the checkout: " << log;
  const SlamRun on = RunSlam(log, std::nullopt, MakeTempDir(), {"--odometry", "log"});
  const SlamRun off = RunSlam(log, std::nullopt, MakeTempDir(), {"--odometry", "log", "--front-recovery", "0"});
  ASSERT_GE(on.ate, 0.0) << on.output;
  ASSERT_GE(off.ate, 0.0) << off.output;
  std::printf("csail log, own odometry: ATE RMSE %.4f m (%.4f m without recovery)\n", on.ate, off.ate);
  EXPECT_LE(on.ate, 0.4);
  EXPECT_EQ(on.wrong, 0) << on.output;
  EXPECT_GT(off.ate, 1.0);
}

// Odometry that errs the same way at every step, 3 % long and drifting 0.02 rad per metre (a wheel
// radius off, wheels of unequal radius): SLAM learns that error from the steps whose walls fixed
// the match and takes it out, and aces ends about where it does without it (seed 1: 0.103 m);
// left in, the corridors, where only the odometry measures a step, stretch by the 3 % (0.249 m).
TEST(NavdReplay, SlamOnTheAcesLogLearnsWhereItsOdometryErrsTheSameWayEveryStep) {
  const std::string log = SourceDir() + "/../shared/data/carmen/aces-corrected.log.gz";
  if (!std::filesystem::exists(log)) GTEST_SKIP() << "shared data not beside the checkout: " << log;
  const std::string biased = "0.05,0.035,0.03,0.02";
  const SlamRun on = RunSlam(log, 1, MakeTempDir(), {"--odom-noise", biased, "--odometry-bias", "on"});
  const SlamRun off = RunSlam(log, 1, MakeTempDir(), {"--odom-noise", biased, "--odometry-bias", "off"});
  ASSERT_GE(on.ate, 0.0) << on.output;
  ASSERT_GE(off.ate, 0.0) << off.output;
  std::printf("aces log, odometry 3 %% long and drifting: ATE RMSE %.4f m learnt, %.4f m not\n", on.ate, off.ate);
  EXPECT_LE(on.ate, 0.15);
  EXPECT_EQ(on.wrong, 0) << on.output;
  EXPECT_GT(off.ate, 0.2);
  double scale = 0.0, drift = 0.0;
  const size_t at = on.output.find("odometry bias learnt: ");
  ASSERT_NE(at, std::string::npos) << on.output;
  ASSERT_EQ(std::sscanf(on.output.c_str() + at, "odometry bias learnt: scale %lf, drift %lf", &scale, &drift), 2);
  EXPECT_NEAR(scale, 1.0 / 1.03, 0.01);
  EXPECT_NEAR(drift, -0.02, 0.01);
  EXPECT_EQ(off.output.find("odometry bias learnt"), std::string::npos) << off.output;
}

// Odometry with twice the default heading noise (0.07 rad per metre), which navd-replay tells SLAM:
// the front end's window widens by it, and aces holds as at the default noise (seed 2 ends
// 0.096 m). With the window the default model opens, this seed ended 0.187 m.
TEST(NavdReplay, SlamOnTheAcesLogHoldsWithTwiceTheHeadingNoiseItIsTold) {
  const std::string log = SourceDir() + "/../shared/data/carmen/aces-corrected.log.gz";
  if (!std::filesystem::exists(log)) GTEST_SKIP() << "shared data not beside the checkout: " << log;
  const SlamRun run = RunSlam(log, 2, MakeTempDir(), {"--odom-noise", "0.05,0.07"});
  ASSERT_GE(run.ate, 0.0) << run.output;
  std::printf("aces log, twice the heading noise: ATE RMSE %.4f m, %d loop closures\n", run.ate, run.closures);
  EXPECT_LE(run.ate, 0.13);
  EXPECT_EQ(run.wrong, 0) << run.output;
}

// CSAIL's robot ends its run back at the start, which it left 400 scans before. Closures on the
// way there reset the drift since the last closure, yet the graph near the start is 0.5-0.8 m off
// where the robot is: only the wider search (as far as the chain can have drifted since the start)
// finds that last closure. With GraphSlamOptions::loop_wide_max_correction at 0 (no wider
// search) this seed ends at 0.161 m.
TEST(NavdReplay, SlamOnTheCsailLogClosesTheLoopBackAtTheStart) {
  const std::string log = SourceDir() + "/../shared/data/carmen/csail-corrected.log.gz";
  if (!std::filesystem::exists(log)) GTEST_SKIP() << "shared data not beside the checkout: " << log;
  const SlamRun run = RunSlam(log, 1, MakeTempDir());
  ASSERT_GE(run.ate, 0.0) << run.output;
  std::printf("CSAIL log, slam: ATE RMSE %.4f m, %d loop closures, %d wrong\n", run.ate, run.closures, run.wrong);
  EXPECT_LE(run.ate, 0.145);
  EXPECT_EQ(run.wrong, 0) << run.output;
}

// Edmonton's convention centre: halls whose walls a scan sees at 10-30 m. Matched up to 20 m
// against references that reach 30 m, a scan's far echoes find their walls in the nodes before
// it; with the references cut at 20 m too (GraphSlamOptions::reference_extra_range 0) this seed
// ended 0.438 m.
TEST(NavdReplay, SlamOnTheEdmontonLogMatchesFarEchoesAgainstFartherReferences) {
  const std::string log = SourceDir() + "/../shared/data/carmen/edmonton-corrected.log.gz";
  if (!std::filesystem::exists(log)) GTEST_SKIP() << "shared data not beside the checkout: " << log;
  const SlamRun run = RunSlam(log, 1, MakeTempDir());
  ASSERT_GE(run.ate, 0.0) << run.output;
  std::printf("Edmonton log, slam: ATE RMSE %.4f m, %d loop closures, %d wrong\n", run.ate, run.closures, run.wrong);
  EXPECT_LE(run.ate, 0.3);
  EXPECT_EQ(run.wrong, 0) << run.output;
}

// A 100 x 70 m hall (a convention centre's) with 0.6 m pillars 25 m apart, driven round a 50 x 20 m
// loop 1.3 times, written as a corrected FLASER log (180 beams, 1 cm range noise, no return 81.91).
// Most scans hold a handful of pillar echoes within 20 m: the walls, 20 to 50 m off, are what
// holds the pose, and are used only because the scans find too little near.
void WriteHallLog(const std::string& path) {
  std::vector<std::array<double, 4>> walls;  // segments x0, y0, x1, y1
  auto box = [&](double x0, double y0, double x1, double y1) {
    walls.push_back({x0, y0, x1, y0});
    walls.push_back({x1, y0, x1, y1});
    walls.push_back({x1, y1, x0, y1});
    walls.push_back({x0, y1, x0, y0});
  };
  box(0, 0, 100, 70);
  for (double x : {25.0, 50.0, 75.0})
    for (double y : {20.0, 45.0}) box(x - 0.3, y - 0.3, x + 0.3, y + 0.3);
  auto cast = [&](double px, double py, double a) {
    const double dx = std::cos(a), dy = std::sin(a);
    double best = 81.91;
    for (const auto& [x0, y0, x1, y1] : walls) {
      const double ex = x1 - x0, ey = y1 - y0, den = dx * ey - dy * ex;
      if (std::abs(den) < 1e-12) continue;
      const double t = ((x0 - px) * ey - (y0 - py) * ex) / den, u = ((x0 - px) * dy - (y0 - py) * dx) / den;
      if (u >= 0 && u <= 1 && t > 0 && t < best) best = t;
    }
    return best;
  };
  const std::vector<std::array<double, 2>> corners{{30, 30}, {80, 30}, {80, 50}, {30, 50}};
  std::vector<std::array<double, 3>> poses;
  for (int leg = 0; leg < 6; ++leg) {
    const auto& a = corners[leg % 4];
    const auto& b = corners[(leg + 1) % 4];
    const double heading = std::atan2(b[1] - a[1], b[0] - a[0]);
    if (!poses.empty()) {  // a quarter turn on the spot
      const double from = poses.back()[2], turn = NormalizeAngle(heading - from);
      for (int i = 1; i <= 5; ++i) poses.push_back({a[0], a[1], from + turn * i / 6.0});
    }
    const int steps = static_cast<int>(std::hypot(b[0] - a[0], b[1] - a[1]) / 0.5);
    for (int i = 0; i < steps; ++i)
      poses.push_back({a[0] + (b[0] - a[0]) * i / steps, a[1] + (b[1] - a[1]) * i / steps, heading});
  }
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::ofstream log(path);
  log.precision(10);
  for (size_t k = 0; k < poses.size(); ++k) {
    const auto& [x, y, theta] = poses[k];
    log << "FLASER 180";
    for (int i = 0; i < 180; ++i) {
      const double r = cast(x, y, theta - M_PI / 2 + i * M_PI / 180);
      log << " " << (r >= 81.91 ? 81.91 : r + noise(rng));
    }
    const double stamp = 1000.0 + 0.5 * k;
    log << " " << x << " " << y << " " << theta << " " << x << " " << y << " " << theta << " " << stamp << " hall "
        << stamp << "\n";
  }
}

TEST(NavdReplay, SlamAndLocalisationHoldInAnOpenHallByItsFarWalls) {
  const std::string dir = MakeTempDir();
  WriteHallLog(dir + "/hall.log");
  const SlamRun run = RunSlam(dir + "/hall.log", 1, dir);
  ASSERT_GE(run.ate, 0.0) << run.output;
  std::printf("open hall, slam: ATE RMSE %.4f m, %d loop closures (median %.3f m off the poses), %d wrong\n", run.ate,
              run.closures, run.closure_median, run.wrong);
  EXPECT_LE(run.ate, 0.1);
  EXPECT_EQ(run.wrong, 0) << run.output;
  // Its poses are exact, so its closures lie within the matcher's own error of them.
  EXPECT_GE(run.closures, 1);
  EXPECT_GE(run.closure_median, 0.0) << run.output;
  EXPECT_LE(run.closure_median, 0.02) << run.output;
  const auto localize = RunCommand(
      {NavdReplayBinary(), "--log", dir + "/hall.log", "--mode", "localize", "--out", dir + "/loc.tum"}, 120.0);
  ASSERT_EQ(localize.exit_code, 0) << localize.output;
  const size_t at = localize.output.find("position RMSE ");
  ASSERT_NE(at, std::string::npos) << localize.output;
  double rmse = -1.0;
  ASSERT_EQ(std::sscanf(localize.output.c_str() + at, "position RMSE %lf", &rmse), 1) << localize.output;
  std::printf("open hall, localize: position RMSE %.4f m\n", rmse);
  EXPECT_LE(rmse, 0.1);
  EXPECT_NE(localize.output.find("never lost"), std::string::npos) << localize.output;
}

// Exploration of the warehouse from an empty map (simulator, SLAM, exploration goals and path
// following in one process): each method maps at least 95% of the reachable free space, without
// a collision. Frontier and greedy stop by themselves when no reachable frontier is left; VFM can
// keep chasing specks of unknown that loop-closure redraws leave, so for it the time limit may end
// the run (exit 3) as long as the map is there.
class NavdExplore : public ::testing::TestWithParam<std::string> {};

TEST_P(NavdExplore, MapsTheWarehouseFromNothing) {
  const auto r = RunCommand({NavdExploreBinary(), "--method", GetParam(), "--max-time", "900"}, 240.0);
  const bool may_time_out = GetParam() == "vfm";
  if (!(may_time_out && r.exit_code == 3)) {
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  double mapped = -1, simulated = -1, driven = -1;
  int collisions = -1;
  const std::string ending = r.exit_code == 0 ? "complete, " : "stopped at --max-time, ";
  const size_t at = r.output.find(ending);
  ASSERT_NE(at, std::string::npos) << r.output;
  ASSERT_EQ(std::sscanf(r.output.c_str() + at + ending.size(), "%lf%%", &mapped), 1) << r.output;
  const size_t sim = r.output.find(" s simulated, ", at);
  ASSERT_NE(sim, std::string::npos);
  ASSERT_EQ(std::sscanf(r.output.c_str() + r.output.rfind(", ", sim) + 2, "%lf s simulated, %lf m driven", &simulated,
                        &driven),
            2);
  const size_t col = r.output.find(" collisions", at);
  ASSERT_NE(col, std::string::npos);
  ASSERT_EQ(std::sscanf(r.output.c_str() + r.output.rfind(", ", col) + 2, "%d collisions", &collisions), 1);
  std::printf("explore (%s): %.1f%% mapped, %.1f s simulated, %.1f m driven, %d collisions\n", GetParam().c_str(),
              mapped, simulated, driven, collisions);
  EXPECT_GE(mapped, 95.0);
  EXPECT_EQ(collisions, 0);
}
INSTANTIATE_TEST_SUITE_P(Methods, NavdExplore, ::testing::Values("greedy", "frontier", "vfm"),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

// navd-explore --record writes the run as a CARMEN log (a scan every 10 Hz, the laser at the true
// pose), and navd-replay's SLAM runs on it like on a corrected log: a line of TUM per scan.
TEST(NavdExplore, RecordsARunThatSlamReplays) {
  const std::string dir = MakeTempDir();
  const auto run = RunCommand(
      {NavdExploreBinary(), "--method", "frontier", "--max-time", "60", "--record", dir + "/run.log"}, 120.0);
  ASSERT_TRUE(run.exit_code == 0 || run.exit_code == 3) << run.output;
  std::ifstream log(dir + "/run.log");
  int scans = 0;
  for (std::string line; std::getline(log, line);) scans += line.rfind("ROBOTLASER1 ", 0) == 0;
  EXPECT_GE(scans, 500);  // 60 s at 10 Hz
  EXPECT_FALSE(std::filesystem::exists(dir + "/run.log.part"));
  const auto r =
      RunCommand({NavdReplayBinary(), "--log", dir + "/run.log", "--mode", "slam", "--out", dir + "/est.tum"}, 120.0);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const size_t rmse = r.output.find("ATE RMSE ");
  ASSERT_NE(rmse, std::string::npos) << r.output;
  double ate = -1;
  ASSERT_EQ(std::sscanf(r.output.c_str() + rmse, "ATE RMSE %lf", &ate), 1);
  std::printf("explore recording: %d scans, SLAM ATE RMSE %.4f m\n", scans, ate);
  EXPECT_LE(ate, 0.10);
  std::ifstream tum(dir + "/est.tum");
  int lines = 0;
  for (std::string line; std::getline(tum, line);) ++lines;
  EXPECT_EQ(lines, scans);
}

// The same seed explores the same way on any machine and at any load: the same report and, to the
// byte, the same recording (the map it plans on is redrawn after loop closures by simulated time,
// MappingSessionOptions::rerender_period, not by how fast the machine runs).
TEST(NavdExplore, TheSameSeedExploresTheSameWay) {
  const std::string dir = MakeTempDir();
  std::string reports[2], logs[2];
  for (int i = 0; i < 2; ++i) {
    const std::string log = dir + "/run" + std::to_string(i) + ".log";
    const auto run = RunCommand(
        {NavdExploreBinary(), "--method", "frontier", "--seed", "3", "--max-time", "300", "--record", log}, 300.0);
    ASSERT_TRUE(run.exit_code == 0 || run.exit_code == 3) << run.output;
    const size_t at = run.output.find("explore (");
    ASSERT_NE(at, std::string::npos) << run.output;
    reports[i] = run.output.substr(at, run.output.find('\n', at) - at);
    logs[i] = ReadTextFile(log, "recording");
  }
  std::printf("%s\n", reports[0].c_str());
  EXPECT_EQ(reports[0], reports[1]);
  EXPECT_FALSE(logs[0].empty());
  EXPECT_TRUE(logs[0] == logs[1]) << "the two recordings differ";
}

// Online replays: a real navd on the map navd-replay builds from one of the shared CARMEN logs,
// and navctl replay playing that log to it over DDS like a robot.
class NavctlReplay : public ::testing::Test {
 protected:
  // The shared log `name`-corrected.log.gz; empty when the shared data is not beside the checkout.
  static std::string SharedLog(const std::string& name) {
    const std::string log = SourceDir() + "/../shared/data/carmen/" + name + "-corrected.log.gz";
    return std::filesystem::exists(log) ? log : "";
  }
  // Builds the log's map and starts navd on it.
  void StartNavdOnMapOf(const std::string& log) {
    log_ = log;
    ASSERT_EQ(
        RunCommand({NavdReplayBinary(), "--log", log, "--mode", "map", "--out", dir_ + "/map.yaml"}, 60.0).exit_code,
        0);
    StackOptions o;
    o.start_sim = false;
    o.navd_args = {"--map", dir_ + "/map.yaml"};
    stack_ = std::make_unique<NavdStack>(o);
  }
  // navctl replay of the log to navd, with `args` after the log, domain and server.
  CommandResult Replay(const std::vector<std::string>& args, double timeout = 120.0) const {
    std::vector<std::string> argv = {NavctlBinary(), "replay",         "--log",
                                     log_,           "--domain",       std::to_string(stack_->domain()),
                                     "--server",     stack_->address()};
    argv.insert(argv.end(), args.begin(), args.end());
    return RunCommand(argv, timeout);
  }
  // The replay's verdict line, "navd: N poses, position RMSE X m, heading RMSE Y rad".
  struct Verdict {
    int poses = 0;
    double rmse = -1, heading = -1;
  };
  static void ReadVerdict(const std::string& output, Verdict* v) {
    const size_t at = output.find("navd: ");
    ASSERT_NE(at, std::string::npos) << output;
    ASSERT_EQ(std::sscanf(output.c_str() + at, "navd: %d poses, position RMSE %lf m, heading RMSE %lf rad", &v->poses,
                          &v->rmse, &v->heading),
              3)
        << output;
  }

  const std::string dir_ = MakeTempDir();
  std::string log_;
  std::unique_ptr<NavdStack> stack_;
};

// Online: navctl replay plays the Intel log over DDS like a robot (log-time clock, corrupted
// odometry, scans) while a real navd localises on the map built from the log, and judges navd's
// published poses (between scans too) against the corrected poses. The first 200 scans (11
// minutes of log) at 50x; the whole log is in the issue note.
TEST_F(NavctlReplay, NavdLocalisesTheIntelLogOverDds) {
  const std::string log = SharedLog("intel");
  if (log.empty()) GTEST_SKIP() << "shared data not beside the checkout";
  ASSERT_NO_FATAL_FAILURE(StartNavdOnMapOf(log));
  const NavdStack& stack = *stack_;
  const auto r = Replay({"--rate", "50", "--max-scans", "200", "--out", dir_ + "/online.tum"});
  ASSERT_EQ(r.exit_code, 0) << r.output << stack.Logs();
  Verdict v;
  ASSERT_NO_FATAL_FAILURE(ReadVerdict(r.output, &v));
  std::printf("online Intel replay: %d poses, position RMSE %.4f m, heading RMSE %.4f rad\n", v.poses, v.rmse,
              v.heading);
  EXPECT_GT(v.poses, 200);
  EXPECT_LE(v.rmse, 0.15) << stack.Logs();
  EXPECT_LE(v.heading, 0.06);
  EXPECT_TRUE(std::filesystem::exists(dir_ + "/online.tum"));
  // A slip: 100 s into the log the odometry slips 3 m over a second while the scans go on; navd
  // follows the scans, never counts the pose lost, and is back within 0.1 m of the truth within
  // 20 s of log time. A kidnap: the robot is carried 3 m (the scans skip ahead, the odometry stands
  // still); navd counts the pose lost and is back within 0.1 m within 20 s of log time.
  for (const std::string kind : {"slip", "kidnap"}) {
    const auto k = Replay({"--rate", "50", "--max-scans", "200", "--" + kind, "100,3,0"});
    ASSERT_EQ(k.exit_code, 0) << k.output << stack.Logs();
    const size_t line = k.output.find(kind + ": ");
    ASSERT_NE(line, std::string::npos) << k.output;
    const size_t back = k.output.find("back within 0.1 m ", line);
    ASSERT_NE(back, std::string::npos) << k.output;
    double back_after = -1;
    ASSERT_EQ(std::sscanf(k.output.c_str() + back, "back within 0.1 m %lf s", &back_after), 1) << k.output;
    std::printf("%s", k.output.substr(line).c_str());
    EXPECT_LE(back_after, 20.0) << k.output;
    const bool lost = k.output.find("navd declared the pose lost", line) != std::string::npos;
    EXPECT_EQ(lost, kind == "kidnap") << k.output;
  }
  for (const std::vector<std::string>& bad : {std::vector<std::string>{"--kidnap", "100,3"},
                                              std::vector<std::string>{"--slip", "100,3,0", "--kidnap", "100,3,0"},
                                              std::vector<std::string>{"--kidnap", "100,300,0"},
                                              std::vector<std::string>{"--pairing", "later", "--odometry", "log"}}) {
    std::vector<std::string> args = {"--max-scans", "200"};
    args.insert(args.end(), bad.begin(), bad.end());
    const auto refused = Replay(args, 30.0);
    EXPECT_NE(refused.exit_code, 0) << bad[1];
    EXPECT_EQ(Lines(refused.output), 1) << refused.output;
    EXPECT_NE(refused.output.find(bad[0]), std::string::npos) << refused.output;
  }
  // No navd on the domain: one line, non-zero.
  const auto lonely = RunCommand({NavctlBinary(), "replay", "--log", log, "--domain", std::to_string(ReserveDomain()),
                                  "--server", "", "--max-scans", "5", "--wait", "1"},
                                 60.0);
  EXPECT_NE(lonely.exit_code, 0);
  EXPECT_EQ(Lines(lonely.output), 1) << lonely.output;
}

// A raw log inside navd: navctl replay sends the aces log's own odometry (its ODOM lines paired
// as its scans agree), while navd maps with SLAM (StartMapping). The map navd
// builds is judged by localising on it offline against the log's corrected poses: a chain broken
// at those turns draws the building twice, crossed, and the localiser ends metres off.
TEST_F(NavctlReplay, NavdMapsTheAcesLogFromItsOwnOdometry) {
  const std::string log = SharedLog("aces");
  if (log.empty()) GTEST_SKIP() << "shared data not beside the checkout";
  ASSERT_NO_FATAL_FAILURE(StartNavdOnMapOf(log));
  // The replay sets navd's pose to the log's first, and mapping starts once the odometry flows.
  // It sends the beams as the scanner gave them (its default cuts them at 15 m, where the
  // localiser's map was drawn): SLAM takes from them what it uses. At 25x navd's SLAM keeps up
  // with the log's scans.
  Process replay({NavctlBinary(), "replay", "--log", log, "--domain", std::to_string(stack_->domain()), "--server",
                  stack_->address(), "--rate", "25", "--range-max", "80", "--odometry", "log"},
                 dir_ + "/replay.log");
  ASSERT_TRUE(stack_->WaitForPose(30.0)) << replay.Log() << stack_->Logs();
  Client& client = stack_->client();
  ASSERT_TRUE(client.StartMapping(v1::MAPPING_MODE_SLAM, 0.05, 120.0).active());
  ASSERT_EQ(replay.Wait(120.0), 0) << replay.Log() << stack_->Logs();
  const v1::MappingStatus stopped = client.StopMapping();
  std::printf("SLAM in navd on aces's own odometry: %llu scans, %llu dropped, %u nodes, %u loop closures\n",
              static_cast<unsigned long long>(stopped.scans()),
              static_cast<unsigned long long>(stopped.dropped_scans()), stopped.nodes(), stopped.loop_closures());
  EXPECT_GE(stopped.scans(), 400u);
  EXPECT_GE(stopped.loop_closures(), 10u);
  client.SaveMap(dir_ + "/built.yaml", v1::MAP_FORMAT_MAP_SERVER, v1::MAP_SOURCE_MAPPING);
  const auto localised = RunCommand({NavdReplayBinary(), "--log", log, "--mode", "localize", "--map",
                                     dir_ + "/built.yaml", "--seed", "1", "--out", dir_ + "/on-built.tum"},
                                    120.0);
  ASSERT_EQ(localised.exit_code, 0) << localised.output;
  // The map's frame is where navd's localiser put the first scan SLAM took (a centimetre or a
  // hundredth of a radian off the log's): the localiser's trajectory on it is judged after SE(2)
  // alignment, which leaves the map's shape.
  const size_t at = localised.output.find("localize: RMSE ");
  ASSERT_NE(at, std::string::npos) << localised.output;
  double aligned = -1.0;
  ASSERT_EQ(std::sscanf(localised.output.c_str() + at, "localize: RMSE %lf m after SE(2) alignment", &aligned), 1);
  std::printf("localised on navd's map: position RMSE %.4f m after SE(2) alignment\n", aligned);
  EXPECT_LE(aligned, 0.2) << localised.output;
}

// csail's stamps are too coarse to time its scans by: the replay paces them from the log's
// odometry, says so, and navd localises it online.
TEST_F(NavctlReplay, PacesTheCsailLogsCoarseStampsAndNavdLocalisesIt) {
  const std::string log = SharedLog("csail");
  if (log.empty()) GTEST_SKIP() << "shared data not beside the checkout";
  ASSERT_NO_FATAL_FAILURE(StartNavdOnMapOf(log));
  const auto r = Replay({"--rate", "25", "--max-scans", "120"});
  ASSERT_EQ(r.exit_code, 0) << r.output << stack_->Logs();
  EXPECT_NE(r.output.find("paced from its odometry"), std::string::npos) << r.output;
  Verdict v;
  ASSERT_NO_FATAL_FAILURE(ReadVerdict(r.output, &v));
  std::printf("online csail replay: %d poses, position RMSE %.4f m\n", v.poses, v.rmse);
  EXPECT_GT(v.poses, 500);
  EXPECT_LE(v.rmse, 0.2) << r.output << stack_->Logs();
}

TEST(Daemons, BadWorldAndMapFilesExitNonZeroWithOneLine) {
  const std::string dir = MakeTempDir();
  std::ofstream(dir + "/broken.yaml") << "map: {size: [10, 10]\n";
  std::ofstream(dir + "/bad.pgm") << "P5 100 100 255\nshort";
  std::ofstream(dir + "/map.yaml") << "image: bad.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n";
  struct Case {
    std::vector<std::string> argv;
    std::string expect;
  };
  const std::vector<Case> cases = {
      {{NavdBinary(), "--world", dir + "/missing.yaml", "--listen", "127.0.0.1:0"}, "missing.yaml"},
      {{NavdBinary(), "--world", dir + "/broken.yaml", "--listen", "127.0.0.1:0"}, "malformed YAML"},
      {{NavdBinary(), "--map", dir + "/map.yaml", "--listen", "127.0.0.1:0"}, "truncated"},
      {{NavsimBinary(), "--world", dir + "/missing.yaml"}, "missing.yaml"},
      {{NavsimBinary(), "--world", dir + "/broken.yaml"}, "malformed YAML"},
      {{NavdBinary(), "--dds-network", "wifi"}, "wifi"},
  };
  for (const auto& c : cases) {
    const auto r = RunCommand(c.argv, 20.0);
    EXPECT_NE(r.exit_code, 0) << c.argv[0] << " " << c.argv[2];
    EXPECT_EQ(Lines(r.output), 1) << r.output;
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << r.output;
  }
}

TEST(Daemons, NavdStopsTheRobotAndExitsCleanlyOnSigterm) {
  // A long watchdog, so only navd's own stop command can halt the robot within the test.
  StackOptions options;
  options.sim_args = {"--command-timeout", "60"};
  NavdStack stack(options);
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  std::thread nav([&] {
    try {
      stack.client().NavigateTo(8.8, 8.8, std::nullopt, {}, 60.0);
    } catch (const ClientError&) {
      // The stream ends when navd goes down.
    }
  });
  for (int i = 0; i < 250 && !stack.client().GetStatus().active(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(stack.navd().Stop(SIGTERM, 10.0), 0) << stack.Logs();
  nav.join();
  EXPECT_NE(stack.navd().Log().find("stopped"), std::string::npos);
  // navsim heard the stop before its watchdog could: check it is standing still.
  EXPECT_TRUE(RobotStandsStill(*stack.MakeTelemetry()));
}

TEST(Daemons, NavdStopsAndReportsWhenSensorsGoStale) {
  for (const bool sim_time : {true, false}) {
    StackOptions options;
    options.use_sim_time = sim_time;
    options.rate = 1.0;
    NavdStack stack(options);
    ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
    // Fresh while the simulator runs (the first status after start-up may predate the laser).
    bool fresh = false;
    for (int i = 0; i < 100 && !fresh; ++i) {
      fresh = !stack.client().GetStatus().sensors_stale();
      if (!fresh) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    EXPECT_TRUE(fresh) << (sim_time ? "with" : "without") << " --use-sim-time";
    stack.sim()->Stop(SIGKILL, 5.0);
    bool stale = false;
    for (int i = 0; i < 100 && !stale; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      stale = stack.client().GetStatus().sensors_stale();
    }
    EXPECT_TRUE(stale) << (sim_time ? "with" : "without") << " --use-sim-time";
  }
}

}  // namespace
}  // namespace navd::testing
