// Waypoint missions end to end on real navsim + navd + navctl over loopback: seed 000's Run 1
// figures, pause/resume, the decision maker's telemetry, and the missions' bad input.
#include <gtest/gtest.h>

#include <signal.h>

#include <nlohmann/json.hpp>
#include <thread>

#include "tests/support/navd_fixture.h"

namespace navd::testing {
namespace {

std::string Scenario(const std::string& name) { return SourceDir() + "/worlds/scenarios/" + name + ".yaml"; }

// Seed 000's delivery rounds: the scenario's targets cyclically until 102 m, judged by navsim's
// ground truth (navctl follow --measure --json). Returns that JSON ("truth" holds the figures) and
// the stack's logs; the JSON is null when the run did not finish.
struct DeliveryRun {
  nlohmann::json result;
  std::string logs;
};
DeliveryRun FirstHundredMetres(const std::string& scenario, int timeout) {
  StackOptions options;
  options.rate = 10.0;
  options.sim_args = {"--scenario", Scenario(scenario)};
  NavdStack stack(options);
  DeliveryRun run;
  if (!stack.WaitForPose(20.0)) {
    ADD_FAILURE() << "no pose\n" << stack.Logs();
    return run;
  }
  const auto follow = RunCommand({NavctlBinary(), "--server", stack.address(), "follow", "--scenario",
                                  Scenario(scenario), "--cyclic", "--max-distance", "102", "--measure", "--domain",
                                  std::to_string(stack.domain()), "--json", "--timeout", std::to_string(timeout)},
                                 timeout + 40.0);
  run.logs = stack.Logs();
  EXPECT_EQ(follow.exit_code, 0) << follow.output << run.logs;
  if (follow.exit_code == 0) run.result = nlohmann::json::parse(follow.output.substr(follow.output.find('{')));
  return run;
}

// Seed 000, Run 1: the warehouse's 11 targets cyclically, robot speed <= 0.5 m/s. The seed's robot
// covered its first 100 m in 256 s with a mean position error of 0.063 m.
TEST(DeliveryE2E, SeedZeroRunOneFirstHundredMetres) {
  const DeliveryRun run = FirstHundredMetres("warehouse_run1", 200);
  ASSERT_FALSE(run.result.is_null());
  const auto& j = run.result;
  const auto& truth = j.at("truth");
  std::printf("run 1: first 100 m in %.1f s, mean position error %.4f m (max %.4f), collisions %d\n",
              truth.value("time_to_first_100m", -1.0), truth.at("mean_position_error").get<double>(),
              truth.at("max_position_error").get<double>(), truth.at("collisions").get<int>());
  EXPECT_EQ(truth.at("collisions").get<int>(), 0);
  ASSERT_TRUE(truth.contains("time_to_first_100m")) << j;
  EXPECT_LE(truth.at("time_to_first_100m").get<double>(), 256.0);
  EXPECT_LE(truth.at("mean_position_error").get<double>(), 0.03);
  EXPECT_GT(truth.at("samples").get<int>(), 1000);
  EXPECT_GE(j.at("waypoints_reached").get<int>(), 22);  // two laps and more
}

// Seed 000, Run 2: Run 1 among three moving obstacles. The seed's robot took 352 s for its first
// 100 m (evasive manoeuvres) with a mean position error of 0.096 m. The robot must detect the
// carts (section 4.4), let the avoidance behaviour take over when one closes in (section 4.5),
// and never drive into one.
TEST(DeliveryE2E, SeedZeroRunTwoAmongMovingObstacles) {
  const DeliveryRun run = FirstHundredMetres("warehouse_run2", 300);
  ASSERT_FALSE(run.result.is_null());
  const auto& truth = run.result.at("truth");
  const std::string& logs = run.logs;
  int manoeuvres = 0;
  for (size_t at = logs.find("avoiding a moving obstacle: "); at != std::string::npos;
       at = logs.find("avoiding a moving obstacle: ", at + 1)) {
    const std::string phase = logs.substr(at + 28, 7);
    manoeuvres += phase == "backing" || phase == "turning";
  }
  std::printf("run 2: first 100 m in %.1f s, mean position error %.4f m (max %.4f), collisions %d, %d evasive moves\n",
              truth.value("time_to_first_100m", -1.0), truth.at("mean_position_error").get<double>(),
              truth.at("max_position_error").get<double>(), truth.at("collisions").get<int>(), manoeuvres);
  EXPECT_EQ(truth.at("collisions").get<int>(), 0) << logs;
  ASSERT_TRUE(truth.contains("time_to_first_100m")) << run.result;
  EXPECT_LE(truth.at("time_to_first_100m").get<double>(), 352.0);
  EXPECT_LE(truth.at("mean_position_error").get<double>(), 0.04) << logs;
  EXPECT_GE(manoeuvres, 1) << "the carts never came close enough to need the avoidance behaviour";
}

TEST(DeliveryE2E, PauseHoldsTheRobotResumeFinishesAndFeedbackExplains) {
  NavdStack stack;
  const auto telemetry = stack.MakeTelemetry();
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  Client& client = stack.client();
  // No mission: nothing to pause or resume, and cancel reports there was nothing active.
  for (const auto& call :
       {std::function<void()>([&] { client.Pause(); }), std::function<void()>([&] { client.Resume(); })}) {
    try {
      call();
      ADD_FAILURE() << "pause/resume without a mission was accepted";
    } catch (const ClientError& e) {
      EXPECT_EQ(e.code(), grpc::StatusCode::FAILED_PRECONDITION) << e.what();
    }
  }
  EXPECT_FALSE(client.Cancel());

  std::thread operator_thread([&] {
    for (int i = 0; i < 300 && !client.GetStatus().active(); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    Client other({stack.address(), 5.0});
    other.Pause();
    EXPECT_TRUE(RobotStandsStill(*telemetry, 0.4, 1.0));
    const auto s = other.GetStatus();
    EXPECT_TRUE(s.paused());
    EXPECT_EQ(s.state(), v1::PAUSED);
    other.Resume();
  });
  v1::FollowWaypointsRequest req;
  for (const auto& [x, y] : {std::pair{0.8, 3.0}, {3.0, 2.6}, {0.8, 1.6}}) {
    auto* w = req.add_waypoints();
    w->set_x(x);
    w->set_y(y);
  }
  std::vector<v1::NavigationFeedback> feedback;
  const auto result = client.FollowWaypoints(
      req, [&](const v1::NavigationFeedback& f) { feedback.push_back(f); }, 150.0);
  operator_thread.join();
  ASSERT_EQ(result.outcome(), v1::SUCCEEDED) << result.message() << stack.Logs();
  EXPECT_EQ(result.waypoints_reached(), 3u);
  EXPECT_GT(result.distance_travelled(), 6.0);
  bool paused = false, explained = false;
  uint32_t highest = 0;
  for (const auto& f : feedback) {
    paused = paused || f.state() == v1::PAUSED;
    highest = std::max(highest, f.mission_index());
    if (f.behaviour() == "navigation" && f.eta() > 0.0 && !f.utilities().empty()) {
      int motors = 0;
      for (const auto& u : f.utilities()) motors += u.motor() && u.active() ? 1 : 0;
      explained = motors == 1;
    }
  }
  EXPECT_TRUE(paused);
  EXPECT_TRUE(explained) << "feedback lacks the behaviour, the ETA or one active motor behaviour";
  EXPECT_EQ(highest, 2u);
  EXPECT_FALSE(client.Cancel());  // the mission has finished
  // The DDS status carries the decision maker too.
  const auto status = telemetry->LatestStatus();
  ASSERT_TRUE(status);
  EXPECT_EQ(status->behaviour(), "navigation");
  EXPECT_FALSE(status->utilities().empty());
}

// Sensors go silent mid-mission (navsim frozen with SIGSTOP): navd stops and reports within the
// sensor timeout, holds the mission, and finishes it once they return (SIGCONT).
TEST(DeliveryE2E, SilentSensorsMidMissionStopReportAndResume) {
  StackOptions options;
  options.rate = 1.0;
  options.use_sim_time = false;  // navd's own clock keeps running while the simulator is frozen
  NavdStack stack(options);
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  std::optional<v1::NavigationResult> result;
  std::thread mission([&] { result = stack.client().NavigateTo(0.8, 3.5, std::nullopt, {}, 120.0); });
  Client watcher({stack.address(), 5.0});
  for (int i = 0; i < 200 && watcher.GetStatus().state() != v1::DRIVING; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ASSERT_EQ(kill(stack.sim()->pid(), SIGSTOP), 0);
  const auto silent = std::chrono::steady_clock::now();
  double reported = -1.0;
  for (int i = 0; i < 100 && reported < 0.0; ++i) {
    const auto s = watcher.GetStatus();
    if (s.sensors_stale() && s.state() == v1::STOPPED_STALE_SENSORS) {
      reported = std::chrono::duration<double>(std::chrono::steady_clock::now() - silent).count();
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  std::printf("silent sensors reported after %.2f s\n", reported);
  EXPECT_GT(reported, 0.0) << "navd never reported the silence";
  EXPECT_LT(reported, 0.5);  // the 0.3 s sensor timeout plus a control period and polling
  EXPECT_TRUE(watcher.GetStatus().active());
  std::this_thread::sleep_for(std::chrono::seconds(2));
  ASSERT_EQ(kill(stack.sim()->pid(), SIGCONT), 0);
  mission.join();
  ASSERT_TRUE(result);
  EXPECT_EQ(result->outcome(), v1::SUCCEEDED) << result->message() << stack.Logs();
}

TEST(DeliveryE2E, BadMissionsAreRejectedWithTheFieldNamed) {
  NavdStack stack;
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  Client& client = stack.client();
  const auto expect = [&](const v1::FollowWaypointsRequest& req, grpc::StatusCode code, const std::string& word) {
    try {
      client.FollowWaypoints(req, {}, 10.0);
      ADD_FAILURE() << "accepted a mission that names " << word;
    } catch (const ClientError& e) {
      EXPECT_EQ(e.code(), code) << e.what();
      EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    }
  };
  v1::FollowWaypointsRequest req;
  expect(req, grpc::StatusCode::INVALID_ARGUMENT, "waypoints");
  auto* a = req.add_waypoints();
  a->set_x(3.0);
  a->set_y(2.6);
  req.set_cyclic(true);
  expect(req, grpc::StatusCode::INVALID_ARGUMENT, "cyclic");
  auto* wall = req.add_waypoints();
  wall->set_x(1.55);  // the corridor's inner wall
  wall->set_y(3.0);
  expect(req, grpc::StatusCode::INVALID_ARGUMENT, "waypoints[1]");
  wall->set_x(25.0);  // outside the map
  expect(req, grpc::StatusCode::INVALID_ARGUMENT, "waypoints[1]");
  wall->set_x(0.8);
  wall->set_y(1.6);
  req.set_cyclic(false);
  req.set_laps(2);
  expect(req, grpc::StatusCode::INVALID_ARGUMENT, "laps");
  req.set_laps(0);
  req.set_max_distance(-1.0);
  expect(req, grpc::StatusCode::INVALID_ARGUMENT, "max_distance");
  EXPECT_FALSE(client.GetStatus().active());
}

}  // namespace
}  // namespace navd::testing
