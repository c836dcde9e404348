// End to end over real processes: navsim and navd on loopback (own DDS domain, free port), the
// robot sent to the default world's three goals through libnavclient, judged by the simulator's
// ground truth.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>

#include "client_lib/telemetry.h"
#include "dds/conversions.h"
#include "services/common/text_file.h"
#include "services/common/world.h"
#include "tests/support/navd_fixture.h"

namespace navd::testing {
namespace {

void ThreeGoals(double rate) {
  StackOptions options;
  options.rate = rate;
  NavdStack stack(options);
  const auto telemetry_ptr = stack.MakeTelemetry();
  const Telemetry& telemetry = *telemetry_ptr;
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();

  const World world = DefaultWorld();
  ASSERT_EQ(world.goals.size(), 3u);
  for (const Pose2& goal : world.goals) {
    size_t feedback = 0;
    const v1::NavigationResult result = stack.client().NavigateTo(
        goal.x, goal.y, std::nullopt, [&](const v1::NavigationFeedback&) { ++feedback; }, 120.0);
    ASSERT_EQ(result.outcome(), v1::SUCCEEDED) << result.message() << "\n" << stack.Logs();
    EXPECT_GT(feedback, 0u);
    // Ground truth from the simulator, a fresh sample taken after arrival.
    const auto truth = telemetry.WaitForSimStatus(5.0);
    ASSERT_TRUE(truth) << "no simulator status over DDS";
    const double error = std::hypot(truth->x() - goal.x, truth->y() - goal.y);
    std::printf("goal (%.2f, %.2f): true position error %.3f m, estimated %.3f m, %.1f s\n", goal.x, goal.y, error,
                result.distance_to_goal(), result.elapsed());
    EXPECT_LT(error, 0.25) << "true pose (" << truth->x() << ", " << truth->y() << ")";
    EXPECT_EQ(truth->collisions(), 0u) << "the simulator reported a collision";
  }
  // The particle filter localised the robot on the laser scans.
  const auto pose = stack.client().GetPose();
  EXPECT_EQ(pose.localizer(), "amcl");
  EXPECT_GT(pose.quality(), 0.5);
  // navd's own telemetry flowed over DDS too: the pose (map frame) and the status.
  EXPECT_GT(telemetry.pose_count(), 0u);
  ASSERT_TRUE(telemetry.LatestPose());
  EXPECT_EQ(telemetry.LatestPose()->header().frame_id(), "map");
  EXPECT_NEAR(telemetry.LatestPose()->pose().pose().position().x(), world.goals.back().x, 0.2);
  EXPECT_GT(telemetry.status_count(), 0u);
  const auto status = telemetry.LatestStatus();
  ASSERT_TRUE(status);
  EXPECT_FALSE(status->active());
}

TEST(NavigationE2E, ThreeGoalsInTheDefaultWorldAtRate10) { ThreeGoals(10.0); }

// navd starts with a wrong pose (0.25 m and 0.12 rad off). The particle filter corrects it from
// the laser while the robot drives, so the robot still arrives where it was sent; dead reckoning
// would carry the initial error to the goal.
TEST(NavigationE2E, LaserLocalisationCorrectsAWrongInitialPose) {
  StackOptions options;
  options.navd_args = {"--initial-pose", "1.0", "1.15", "1.45"};  // truth: (0.8, 1.0, 1.5708)
  NavdStack stack(options);
  const auto telemetry_ptr = stack.MakeTelemetry();
  const Telemetry& telemetry = *telemetry_ptr;
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  const auto result = stack.client().NavigateTo(3.0, 2.6, std::nullopt, {}, 120.0);
  ASSERT_EQ(result.outcome(), v1::SUCCEEDED) << result.message() << stack.Logs();
  const auto truth = telemetry.WaitForSimStatus(5.0);
  ASSERT_TRUE(truth);
  const double error = std::hypot(truth->x() - 3.0, truth->y() - 2.6);
  std::printf("wrong initial pose: true position error at the goal %.3f m\n", error);
  EXPECT_LT(error, 0.12);
  EXPECT_EQ(truth->collisions(), 0u);
}

// Wake-up (seed 000 section 7), automatically: navd is told a pose metres away from the truth. The
// scans stop fitting, the executive declares the pose lost after 3 s, the wake-up behaviour takes
// the robot, relocalises over the whole map and turns in place until the estimate fits; then the
// estimate is back on the true pose.
TEST(NavigationE2E, WakeUpRelocalisesAutomaticallyWhenThePoseIsLost) {
  StackOptions options;
  options.rate = 5.0;
  NavdStack stack(options);
  std::atomic<bool> woke{false};
  TelemetryOptions topts;
  topts.dds.domain = stack.domain();
  topts.dds.name = "test";
  Telemetry telemetry(topts, [&](const navd_msgs::msg::dds_::NavStatus_& m) {
    if (m.behaviour() == "wake_up") woke = true;
  });
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  // Out of the start corridor first: along a featureless corridor no search can tell where it is.
  ASSERT_EQ(stack.client().NavigateTo(3.0, 2.6, std::nullopt, {}, 120.0).outcome(), v1::SUCCEEDED) << stack.Logs();
  ASSERT_TRUE(telemetry.WaitForSimStatus(5.0));
  stack.client().SetPose(4.0, 5.0, -1.0);  // free space metres away; truth near (3.0, 2.6)
  bool found = false;
  double error = 0, heading = 0;
  for (int i = 0; i < 300 && !found; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const auto truth = telemetry.LatestSimStatus();
    const auto pose = stack.client().GetPose();
    if (!truth) continue;
    error = std::hypot(pose.pose().x() - truth->x(), pose.pose().y() - truth->y());
    heading = std::abs(NormalizeAngle(pose.pose().theta() - truth->theta()));
    found = woke && error < 0.15 && heading < 0.1;
  }
  std::printf("wake-up: behaviour seen %d; estimate %.3f m / %.3f rad from the truth\n", woke.load(), error, heading);
  EXPECT_TRUE(woke.load()) << stack.Logs();
  EXPECT_TRUE(found) << stack.Logs();
  EXPECT_EQ(telemetry.LatestSimStatus()->collisions(), 0u);
}

// navd computes odometry itself from the wheel encoders (rt/joint_states) instead of reading the
// robot's rt/odom, and still gets the robot to its goal.
TEST(NavigationE2E, NavigatesWithOdometryFromTheWheelEncoders) {
  StackOptions options;
  options.navd_args = {"--odometry", "encoders"};
  NavdStack stack(options);
  const auto telemetry = stack.MakeTelemetry();
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  const auto result = stack.client().NavigateTo(3.0, 2.6, std::nullopt, {}, 120.0);
  ASSERT_EQ(result.outcome(), v1::SUCCEEDED) << result.message() << stack.Logs();
  const auto truth = telemetry->WaitForSimStatus(5.0);
  ASSERT_TRUE(truth);
  EXPECT_LT(std::hypot(truth->x() - 3.0, truth->y() - 2.6), 0.12);
  EXPECT_EQ(truth->collisions(), 0u);
}

TEST(NavigationE2E, StreamReportsProgressAndCancelStopsTheRobot) {
  StackOptions options;
  options.sim_args = {"--command-timeout", "60"};  // only navd's stop can halt the robot
  NavdStack stack(options);
  const auto telemetry_ptr = stack.MakeTelemetry();
  const Telemetry& telemetry = *telemetry_ptr;
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();

  std::thread canceller([&] {
    // Let the robot get going, then cancel through a second call.
    for (int i = 0; i < 200 && !stack.client().GetStatus().active(); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    Client other({stack.address(), 5.0});
    EXPECT_TRUE(other.Cancel());
  });
  std::vector<double> remaining;
  const auto result = stack.client().NavigateTo(
      8.8, 8.8, std::nullopt, [&](const v1::NavigationFeedback& f) { remaining.push_back(f.distance_remaining()); },
      60.0);
  canceller.join();
  EXPECT_EQ(result.outcome(), v1::CANCELED);
  ASSERT_FALSE(remaining.empty());
  // The robot stops: its true position no longer changes.
  EXPECT_TRUE(RobotStandsStill(telemetry, 0.5, 1.0));
  EXPECT_FALSE(stack.client().GetStatus().active());
}

// Seed 000's long-term memory through navd: navd starts on a warehouse map that lacks the wall
// above the lower-left room (navsim's warehouse has it), so in that room the scans fit its map
// poorly. A client loads the true map over gRPC; the long-term memory hands it to the localisers,
// and the scans fit again.
TEST(NavigationE2E, AMapLoadedOverGrpcReachesTheLocalisers) {
  std::string world = ReadTextFile(SourceDir() + "/worlds/warehouse.yaml", "world");
  for (const std::string line : {"    - [1.6, 3.4, 3.5, 3.5]\n", "    - [4.5, 3.4, 6.0, 3.5]\n"}) {
    const size_t at = world.find(line);
    ASSERT_NE(at, std::string::npos) << line;
    world.erase(at, line.size());
  }
  const std::string path = MakeTempDir() + "/no_wall.yaml";
  std::ofstream(path) << world;
  StackOptions options;
  options.navd_args = {"--world", path};
  NavdStack stack(options);
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  Client& client = stack.client();
  ASSERT_EQ(client.NavigateTo(3.0, 2.6, std::nullopt, {}, 120.0).outcome(), v1::SUCCEEDED) << stack.Logs();
  ASSERT_EQ(client.NavigateTo(5.0, 2.6, std::nullopt, {}, 120.0).outcome(), v1::SUCCEEDED) << stack.Logs();
  const double before = client.GetPose().quality();
  client.LoadMap(SourceDir() + "/worlds/warehouse.yaml");
  ASSERT_EQ(client.NavigateTo(3.0, 2.6, std::nullopt, {}, 120.0).outcome(), v1::SUCCEEDED) << stack.Logs();
  const double after = client.GetPose().quality();
  std::printf("scan fit in the lower-left room: %.2f on the map without the wall, %.2f once the true map is loaded\n",
              before, after);
  EXPECT_GT(after, before + 0.1);
  EXPECT_GT(after, 0.8);
}

// Speed limits by zone: the warehouse with a 0.15 m/s zone across its corridor, in the world file
// navd starts from. The robot, sent up the corridor, drives through the zone no faster than that
// by the simulator's ground truth, and faster elsewhere; clients read and replace the zones over
// gRPC and navctl, and bad zones are refused, keeping the old ones.
TEST(NavigationE2E, SpeedZonesSlowTheRobotWhereTheWorldSaysAndClientsChangeThem) {
  const std::string path = MakeTempDir() + "/zoned.yaml";
  std::ofstream(path) << ReadTextFile(SourceDir() + "/worlds/warehouse.yaml", "world")
                      << "speed_zones:\n  - {name: corridor, box: [0.1, 4.0, 1.5, 6.0], max_speed: 0.15}\n";
  StackOptions options;
  options.navd_args = {"--world", path};
  NavdStack stack(options);
  const auto telemetry = stack.MakeTelemetry();
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  Client& client = stack.client();
  const v1::SpeedZones zones = client.GetSpeedZones();
  ASSERT_EQ(zones.zones_size(), 1);
  EXPECT_EQ(zones.zones(0).name(), "corridor");
  EXPECT_DOUBLE_EQ(zones.zones(0).max_speed(), 0.15);

  // True speeds over 0.2 s of simulated time, by where the robot was.
  std::mutex mutex;
  std::vector<std::pair<double, double>> speeds;  // (y, m/s)
  std::atomic<bool> done{false};
  std::thread sampler([&] {
    std::optional<std::tuple<double, double, double>> last;  // t, x, y
    while (!done) {
      if (const auto m = telemetry->LatestGroundTruth()) {
        const double t = dds::FromTime(m->header().stamp());
        const double x = m->pose().pose().position().x(), y = m->pose().pose().position().y();
        if (!last || t < std::get<0>(*last)) {
          last = {t, x, y};
        } else if (t - std::get<0>(*last) >= 0.2) {
          const double v = std::hypot(x - std::get<1>(*last), y - std::get<2>(*last)) / (t - std::get<0>(*last));
          std::lock_guard<std::mutex> lock(mutex);
          speeds.emplace_back(0.5 * (y + std::get<2>(*last)), v);
          last = {t, x, y};
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
  double limit_seen = 0.0;
  const auto result = client.NavigateTo(
      0.8, 8.5, std::nullopt,
      [&](const v1::NavigationFeedback& f) {
        if (std::abs(f.speed_limit() - 0.15) < 1e-9) limit_seen = f.speed_limit();
      },
      120.0);
  done = true;
  sampler.join();
  ASSERT_EQ(result.outcome(), v1::SUCCEEDED) << result.message() << stack.Logs();
  EXPECT_DOUBLE_EQ(limit_seen, 0.15) << "the feedback never carried the zone's limit";
  double inside = 0.0, outside = 0.0;
  int inside_samples = 0;
  for (const auto& [y, v] : speeds) {
    if (y >= 4.0 && y <= 6.0) {
      inside = std::max(inside, v);
      ++inside_samples;
    } else if (y < 3.4 || y > 6.6) {
      outside = std::max(outside, v);
    }
  }
  std::printf("speed zone: fastest %.3f m/s inside (%d samples), %.3f m/s outside\n", inside, inside_samples, outside);
  EXPECT_GT(inside_samples, 20);
  EXPECT_LE(inside, 0.15 * 1.05 + 0.005);
  EXPECT_GT(outside, 0.3);

  // A bad zone is refused naming the field, and the zones stay as they were.
  v1::SetSpeedZonesRequest bad;
  v1::SpeedZone* z = bad.add_zones();
  z->set_name("bay");
  for (const auto& [x, y] : {std::pair{2.0, 2.0}, {3.0, 2.0}, {3.0, 3.0}}) {
    v1::Point2D* p = z->add_area();
    p->set_x(x);
    p->set_y(y);
  }
  z->set_max_speed(-1.0);
  try {
    client.SetSpeedZones(bad);
    ADD_FAILURE() << "a negative max_speed was accepted";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_NE(std::string(e.what()).find("zones[0].max_speed"), std::string::npos) << e.what();
  }
  EXPECT_EQ(client.GetSpeedZones().zones_size(), 1);

  // navctl replaces and clears them.
  auto navctl = [&](std::vector<std::string> args) {
    args.insert(args.begin(), {NavctlBinary(), "--server", stack.address(), "speed-zones"});
    return RunCommand(args);
  };
  const auto set = navctl({"--set", "door:0,0,1,1:0.1", "--set", "bay:2,2,3,3:0.2"});
  EXPECT_EQ(set.exit_code, 0) << set.output;
  EXPECT_NE(set.output.find("door: at most 0.10 m/s within (0.00, 0.00) (1.00, 0.00) (1.00, 1.00) (0.00, 1.00)"),
            std::string::npos)
      << set.output;
  EXPECT_EQ(client.GetSpeedZones().zones_size(), 2);
  const auto malformed = navctl({"--set", "door:0,0,1:0.1"});
  EXPECT_NE(malformed.exit_code, 0);
  EXPECT_NE(malformed.output.find("--set door"), std::string::npos) << malformed.output;
  const auto cleared = navctl({"--clear"});
  EXPECT_EQ(cleared.exit_code, 0) << cleared.output;
  EXPECT_NE(cleared.output.find("no speed zones"), std::string::npos) << cleared.output;
  EXPECT_EQ(client.GetSpeedZones().zones_size(), 0);
}

// A delivery mission through navctl: three tasks in the warehouse, two loads at a time, the mail
// first (priority 1), back to the start at the end. navd orders the six stops, drives them without
// touching anything, and its round is shorter than doing the tasks one by one in the order given.
// A stop in a wall is refused before the robot moves, naming it.
TEST(NavigationE2E, DeliveryMissionSchedulesPickupsAndDropoffsAndDrivesThem) {
  StackOptions options;
  options.rate = 10.0;
  NavdStack stack(options);
  const auto telemetry_ptr = stack.MakeTelemetry();
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  const std::string server = stack.address();

  const auto bad = RunCommand({NavctlBinary(), "--server", server, "deliver", "--task", "a:0.8,8.5:5.0,5.0", "--task",
                               "b:100,100:1,1", "--plan-only"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("tasks[1].pickup"), std::string::npos) << bad.output;
  EXPECT_FALSE(stack.client().GetStatus().active());

  const auto run = RunCommand({NavctlBinary(), "--server", server, "deliver", "--task", "tools:8.8,8.8:0.8,5.0",
                               "--task", "parts:8.6,5.6:0.8,8.5", "--task", "mail:5.0,5.0:3.0,2.6:1", "--capacity", "2",
                               "--return", "--json", "--timeout", "250"},
                              270.0);
  ASSERT_NE(run.output.find('{'), std::string::npos) << run.output << stack.Logs();
  const auto j = nlohmann::json::parse(run.output.substr(run.output.find('{')));
  const auto& schedule = j.at("schedule");
  std::string order;
  for (const auto& stop : schedule.at("stops")) {
    order += stop.at("action").get<std::string>() + " " + stop.at("name").get<std::string>() + ", ";
  }
  std::printf("delivery: %s; %.2f m planned (%.2f m in the order given), %.2f s to schedule; %s, %.1f s\n",
              order.c_str(), schedule.at("length").get<double>(), schedule.at("given_order_length").get<double>(),
              schedule.at("planning_time").get<double>(), j.at("outcome").get<std::string>().c_str(),
              j.at("elapsed").get<double>());
  EXPECT_EQ(run.exit_code, 0) << run.output << stack.Logs();
  EXPECT_EQ(j.at("outcome"), "succeeded");
  EXPECT_EQ(j.at("stops_reached").get<int>(), 7);  // six stops and the way back
  ASSERT_EQ(schedule.at("stops").size(), 6u);
  EXPECT_LT(schedule.at("length").get<double>(), schedule.at("given_order_length").get<double>());
  // The mail (priority 1) is delivered before anything else; never more than two loads aboard.
  int load = 0;
  for (const auto& stop : schedule.at("stops")) {
    load += stop.at("action") == "pickup" ? 1 : -1;
    EXPECT_LE(load, 2);
    if (stop.at("action") == "dropoff") {
      EXPECT_EQ(stop.at("name"), "mail");
      break;
    }
  }
  const auto truth = telemetry_ptr->WaitForSimStatus(5.0);
  ASSERT_TRUE(truth);
  EXPECT_EQ(truth->collisions(), 0u);
  const Pose2 start = DefaultWorld().start;  // back where it started
  EXPECT_NEAR(truth->x(), start.x, 0.25);
  EXPECT_NEAR(truth->y(), start.y, 0.25);
}

}  // namespace
}  // namespace navd::testing
