// Exploration inside navd, end to end: navd starts a SLAM run, serves its map as it grows,
// localises from the SLAM poses and drives the robot to the exploration goals through its
// executive until no frontier is left. Judged by navsim's ground truth (collisions, distance) and
// by the world's own map (the share of the reachable free space the served map shows), through
// `navctl explore start --wait --measure`, the command docs/usage.md gives.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <thread>

#include "client_lib/telemetry.h"
#include "tests/support/navd_fixture.h"

namespace navd::testing {
namespace {

// Runs f, expects a ClientError with `code` whose message contains `word`.
void ExpectError(const std::function<void()>& f, grpc::StatusCode code, const std::string& word) {
  try {
    f();
    ADD_FAILURE() << "no error";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
  }
}

TEST(ExplorationE2E, FrontierExplorationMapsTheWarehouseThroughNavdWithoutCollisions) {
  StackOptions options;
  options.rate = 4.0;
  NavdStack stack(options);
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  const auto run = RunCommand(
      {NavctlBinary(), "--server", stack.address(), "explore", "start", "--method", "frontier", "--size", "40",
       "--max-time", "900", "--wait", "--measure", "--domain", std::to_string(stack.domain()), "--json"},
      280.0);
  ASSERT_EQ(run.exit_code, 0) << run.output << stack.Logs();
  const auto j = nlohmann::json::parse(run.output.substr(run.output.find('{')));
  const auto& truth = j["truth"];
  std::printf(
      "exploration (frontier, through navd): %.1f%% of the reachable free space mapped (%.1f%% free), "
      "%.1f s simulated, %.1f m driven, %d collisions, %d goals (%d given up), SLAM position error mean "
      "%.3f m max %.3f m\n",
      100.0 * truth["reachable_mapped"].get<double>(), 100.0 * truth["reachable_mapped_free"].get<double>(),
      j["elapsed"].get<double>(), truth["distance_travelled"].get<double>(), truth["collisions"].get<int>(),
      j["goals"].get<int>(), j["goals_given_up"].get<int>(), truth["mean_position_error"].get<double>(),
      truth["max_position_error"].get<double>());
  EXPECT_EQ(j["state"], "complete") << j.dump();
  EXPECT_GE(truth["reachable_mapped"].get<double>(), 0.95) << j.dump();
  EXPECT_EQ(truth["collisions"].get<int>(), 0) << j.dump() << stack.Logs();
  EXPECT_LT(truth["mean_position_error"].get<double>(), 0.15) << j.dump();

  // The map built is the served map now, and the mapping run has ended.
  Client& client = stack.client();
  EXPECT_EQ(client.GetMap(true).info().name(), "explored");
  EXPECT_FALSE(client.GetMappingStatus().active());
  EXPECT_EQ(client.GetPose().localizer(), "slam");
}

TEST(ExplorationE2E, BadRequestsAreRefusedAndStopEndsTheRunKeepingItsMap) {
  StackOptions options;
  options.rate = 4.0;
  NavdStack stack(options);
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  Client& client = stack.client();
  EXPECT_EQ(client.GetExplorationStatus().state(), v1::EXPLORATION_STATE_IDLE);
  ExpectError([&] { client.StopExploration(); }, grpc::StatusCode::FAILED_PRECONDITION, "not exploring");
  auto request = [](auto edit) {
    v1::StartExplorationRequest r;
    edit(r);
    return r;
  };
  ExpectError(
      [&] { client.StartExploration(request([](auto& r) { r.set_method(static_cast<v1::ExplorationMethod>(7)); })); },
      grpc::StatusCode::INVALID_ARGUMENT, "method");
  ExpectError([&] { client.StartExploration(request([](auto& r) { r.set_max_time(-1.0); })); },
              grpc::StatusCode::INVALID_ARGUMENT, "max_time");
  ExpectError([&] { client.StartExploration(request([](auto& r) { r.set_planner("nope"); })); },
              grpc::StatusCode::INVALID_ARGUMENT, "planner");
  ExpectError([&] { client.StartExploration(request([](auto& r) { r.set_size(1e6); })); },
              grpc::StatusCode::INVALID_ARGUMENT, "size");
  // A known-poses mapping run cannot be explored on.
  client.StartMapping(v1::MAPPING_MODE_KNOWN_POSES, 0.05, 20.0);
  ExpectError([&] { client.StartExploration({}); }, grpc::StatusCode::FAILED_PRECONDITION, "known-poses");
  client.StopMapping();
  // None of that started anything or took the robot.
  EXPECT_EQ(client.GetExplorationStatus().state(), v1::EXPLORATION_STATE_IDLE);
  EXPECT_NE(client.GetPose().localizer(), "slam");

  const v1::ExplorationStatus started = client.StartExploration(request([](auto& r) { r.set_size(30.0); }));
  EXPECT_EQ(started.state(), v1::EXPLORATION_STATE_EXPLORING);
  EXPECT_TRUE(started.mapping().active());
  EXPECT_EQ(client.GetPose().localizer(), "slam");
  ExpectError([&] { client.StartExploration({}); }, grpc::StatusCode::FAILED_PRECONDITION, "exploring already");

  // Progress: area explored and goals, while the robot drives.
  v1::ExplorationStatus progress;
  for (int i = 0; i < 100; ++i) {
    progress = client.GetExplorationStatus();
    if (progress.explored_area() > 15.0 && progress.goals() >= 2) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  EXPECT_GT(progress.explored_area(), 15.0) << progress.DebugString();
  EXPECT_GE(progress.goals(), 2u) << progress.DebugString();
  EXPECT_GT(progress.distance_travelled(), 0.1) << progress.DebugString();

  const v1::ExplorationStatus stopped = client.StopExploration();
  EXPECT_EQ(stopped.state(), v1::EXPLORATION_STATE_STOPPED);
  EXPECT_FALSE(stopped.mapping().active());
  EXPECT_FALSE(client.GetStatus().active());
  const v1::GetMapResponse served = client.GetMap(true);
  EXPECT_EQ(served.info().name(), "explored");
  EXPECT_EQ(served.info().width(), 600u);  // 30 m at 5 cm
  const auto telemetry = stack.MakeTelemetry();
  EXPECT_TRUE(RobotStandsStill(*telemetry, 0.5, 1.0));
  ExpectError([&] { client.StopExploration(); }, grpc::StatusCode::FAILED_PRECONDITION, "not exploring");
}

}  // namespace
}  // namespace navd::testing
