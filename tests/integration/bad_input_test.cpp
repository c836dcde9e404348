// Every bad input of the foundation issue, against a real navd over gRPC: the status code, and
// a message that names the problem. navd keeps serving afterwards.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <thread>

#include "services/common/map_server_format.h"
#include "tests/support/navd_fixture.h"

namespace navd::testing {
namespace {

class BadInput : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { stack_ = new NavdStack(); }
  static void TearDownTestSuite() {
    delete stack_;
    stack_ = nullptr;
  }
  void SetUp() override { ASSERT_TRUE(stack_->WaitForPose(20.0)) << stack_->Logs(); }
  Client& client() { return stack_->client(); }

  // Runs f, expects a ClientError with `code` whose message contains every one of `words`.
  void ExpectError(const std::function<void()>& f, grpc::StatusCode code, const std::vector<std::string>& words) {
    try {
      f();
      ADD_FAILURE() << "no error";
    } catch (const ClientError& e) {
      EXPECT_EQ(e.code(), code) << e.what();
      for (const auto& w : words) EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << e.what();
    }
    // Still serving.
    EXPECT_NO_THROW(client().GetPose());
  }
  static NavdStack* stack_;
};
NavdStack* BadInput::stack_ = nullptr;

TEST_F(BadInput, GoalOutsideTheMap) {
  ExpectError([&] { client().ComputePath(1, 1, 25, 3); }, grpc::StatusCode::INVALID_ARGUMENT,
              {"goal", "outside the map"});
  ExpectError([&] { client().NavigateTo(-4, 3); }, grpc::StatusCode::INVALID_ARGUMENT, {"goal", "outside the map"});
}

TEST_F(BadInput, GoalInsideAnObstacle) {
  // The elevator shaft.
  ExpectError([&] { client().ComputePath(0.8, 1, 8.5, 1.5); }, grpc::StatusCode::INVALID_ARGUMENT,
              {"goal", "inside an obstacle"});
  ExpectError([&] { client().NavigateTo(8.5, 1.5); }, grpc::StatusCode::INVALID_ARGUMENT,
              {"goal", "inside an obstacle"});
}

TEST_F(BadInput, NonFiniteCoordinates) {
  ExpectError([&] { client().ComputePath(NAN, 1, 3, 3); }, grpc::StatusCode::INVALID_ARGUMENT, {"start.x", "finite"});
  ExpectError([&] { client().ComputePath(1, 1, 3, INFINITY); }, grpc::StatusCode::INVALID_ARGUMENT,
              {"goal.y", "finite"});
  ExpectError([&] { client().NavigateTo(NAN, 3); }, grpc::StatusCode::INVALID_ARGUMENT, {"goal.x", "finite"});
  ExpectError([&] { client().NavigateTo(3, 2.6, NAN); }, grpc::StatusCode::INVALID_ARGUMENT, {"goal.theta"});
  ExpectError([&] { client().SetPose(1, INFINITY, 0); }, grpc::StatusCode::INVALID_ARGUMENT, {"pose.y"});
}

TEST_F(BadInput, SetPoseOffTheMapOrInAWallIsRefusedAndTheEstimateKept) {
  const auto before = client().GetPose();
  ExpectError([&] { client().SetPose(-3, 2, 0); }, grpc::StatusCode::INVALID_ARGUMENT, {"pose", "outside the map"});
  ExpectError([&] { client().SetPose(0.02, 5, 0); }, grpc::StatusCode::INVALID_ARGUMENT,
              {"pose", "inside an obstacle"});
  const auto after = client().GetPose();
  EXPECT_NEAR(after.pose().x(), before.pose().x(), 0.05);
  EXPECT_NEAR(after.pose().y(), before.pose().y(), 0.05);
}

// navd with no robot (no simulator): no odometry has arrived, so there is no pose to give.
TEST(BadInputWithoutARobot, PoseBeforeAnySensorDataIsAFailedPrecondition) {
  StackOptions o;
  o.start_sim = false;
  NavdStack stack(o);
  try {
    stack.client().GetPose();
    ADD_FAILURE() << "GetPose answered without odometry";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::FAILED_PRECONDITION) << e.what();
    EXPECT_NE(std::string(e.what()).find("odometry"), std::string::npos) << e.what();
  }
}

// A 4000 x 4000 map (16 MB, four times gRPC's default message limit) loads and comes back whole
// through GetMap's row chunks.
TEST(LargeMaps, FourThousandSquareMapTravelsInChunks) {
  StackOptions o;
  o.start_sim = false;
  NavdStack stack(o);
  OccupancyGrid big(4000, 4000, 0.05, Point2::Zero());
  big.FillBox({10.0, 20.0}, {190.0, 20.5});  // a long wall
  big.set({3999, 3999}, OccupancyGrid::kOccupied);
  const std::string path = stack.dir() + "/big.yaml";
  SaveMapServerMap(big, path);
  const v1::MapInfo loaded = stack.client().LoadMap(path);
  EXPECT_EQ(loaded.width(), 4000u);
  const v1::GetMapResponse map = stack.client().GetMap();
  ASSERT_EQ(map.info().width(), 4000u);
  ASSERT_EQ(map.info().height(), 4000u);
  ASSERT_EQ(map.cells().size(), 4000u * 4000u);
  EXPECT_EQ(static_cast<int8_t>(map.cells()[static_cast<size_t>(3999) * 4000 + 3999]), 100);
  EXPECT_EQ(static_cast<int8_t>(map.cells()[static_cast<size_t>(405) * 4000 + 1000]), 100);  // on the wall
  EXPECT_EQ(static_cast<int8_t>(map.cells()[0]), 0);
}

TEST_F(BadInput, WaypointInsideAnObstacleIsNamed) {
  ExpectError(
      [&] {
        client().ComputePathThroughPoses(0.8, 1, {{3.0, 2.6}, {8.5, 1.5}, {8.8, 8.8}});
      },
      grpc::StatusCode::INVALID_ARGUMENT, {"waypoints[1]", "inside an obstacle"});
  const auto ok = client().ComputePathThroughPoses(0.8, 1, {{3.0, 2.6}, {8.8, 8.8}});
  EXPECT_GT(ok.length(), 10.0);
  // Every plan carries its time-optimal velocity profile: at rest at both ends, never above the
  // robot's top speed, times rising to the total duration.
  ASSERT_EQ(ok.speeds_size(), ok.path_size());
  ASSERT_EQ(ok.times_size(), ok.path_size());
  EXPECT_DOUBLE_EQ(ok.speeds(0), 0.0);
  EXPECT_DOUBLE_EQ(ok.speeds(ok.speeds_size() - 1), 0.0);
  for (int i = 1; i < ok.times_size(); ++i) {
    EXPECT_GT(ok.times(i), ok.times(i - 1));
    EXPECT_LE(ok.speeds(i), 0.5 + 1e-9);
  }
  EXPECT_GT(ok.duration(), ok.length() / 0.5);
  EXPECT_NEAR(ok.times(ok.times_size() - 1), ok.duration(), 0.05);
}

TEST_F(BadInput, DeliveryTasksAreCheckedAndNamed) {
  v1::DeliverRequest r;
  ExpectError([&] { client().PlanDeliveries(r); }, grpc::StatusCode::INVALID_ARGUMENT, {"tasks", "at least one"});
  v1::DeliveryTask* ok = r.add_tasks();
  ok->mutable_pickup()->set_x(3.0);
  ok->mutable_pickup()->set_y(2.6);
  ok->mutable_dropoff()->set_x(8.8);
  ok->mutable_dropoff()->set_y(8.8);
  v1::DeliveryTask* bad = r.add_tasks();
  bad->mutable_pickup()->set_x(3.0);
  bad->mutable_pickup()->set_y(2.6);
  ExpectError([&] { client().PlanDeliveries(r); }, grpc::StatusCode::INVALID_ARGUMENT, {"tasks[1].dropoff", "missing"});
  bad->mutable_dropoff()->set_x(8.5);
  bad->mutable_dropoff()->set_y(1.5);
  ExpectError([&] { client().PlanDeliveries(r); }, grpc::StatusCode::INVALID_ARGUMENT,
              {"tasks[1].dropoff", "inside an obstacle"});
  bad->mutable_dropoff()->set_x(NAN);
  ExpectError([&] { client().PlanDeliveries(r); }, grpc::StatusCode::INVALID_ARGUMENT, {"tasks[1].dropoff", "finite"});
  r.mutable_tasks()->RemoveLast();
  const v1::DeliverySchedule schedule = client().PlanDeliveries(r);
  ASSERT_EQ(schedule.stops_size(), 2);
  EXPECT_TRUE(schedule.stops(0).pickup());
  EXPECT_EQ(schedule.stops(0).name(), "task 1");
  EXPECT_GT(schedule.length(), 10.0);
}

// Time-budgeted plans end at the caller's deadline with DEADLINE_EXCEEDED, and brief plans are
// served while several of them run (they hold up no thread that serves others).
TEST_F(BadInput, LongPlansEndAtTheDeadlineWhileBriefPlansGoOn) {
  constexpr int kLong = 4;
  std::atomic<int> long_done{0};
  std::vector<std::string> errors(kLong);
  std::vector<double> seconds(kLong, 0.0);
  std::vector<std::thread> long_plans;
  long_plans.reserve(kLong);
  for (int i = 0; i < kLong; ++i) {
    long_plans.emplace_back([&, i] {
      Client impatient({stack_->address(), 1.5});
      const auto t0 = std::chrono::steady_clock::now();
      try {
        impatient.ComputePath(0.8, 1, 8.8, 8.8, "rrt_star", {{"time_limit", 20.0}});
        errors[i] = "no error";
      } catch (const ClientError& e) {
        errors[i] = grpc::StatusCode::DEADLINE_EXCEEDED == e.code() ? "" : e.what();
      }
      seconds[i] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      ++long_done;
    });
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the long plans are under way
  int brief = 0;
  while (long_done == 0 && brief < 200) {
    EXPECT_EQ(client().ComputePath(0.8, 1, 8.8, 8.8, "astar").planner(), "astar");
    ++brief;
  }
  for (auto& t : long_plans) t.join();
  for (int i = 0; i < kLong; ++i) {
    EXPECT_EQ(errors[i], "") << "long plan " << i;
    EXPECT_LT(seconds[i], 6.0) << "long plan " << i;
  }
  EXPECT_GE(brief, 5) << "brief plans were not served during the long ones";
  EXPECT_NO_THROW(client().ComputePath(0.8, 1, 8.8, 8.8, "rrt_star", {{"time_limit", 0.2}}));
}

// Moving bodies reach the planners that use them: the kinodynamic planner's trajectory misses a
// person standing on the straight line, with speeds per point; bad bodies are named.
TEST_F(BadInput, MovingBodiesReachTheKinodynamicPlannerAndBadOnesAreNamed) {
  v1::MovingBody person;
  person.mutable_position()->set_x(2.5);
  person.mutable_position()->set_y(2.2);
  person.mutable_velocity();
  person.set_radius(0.25);
  person.set_person(true);
  const auto plan =
      client().ComputePath(0.8, 1, 3, 2.6, "kinodynamic", {{"time_limit", 10.0}, {"algorithm", 2}}, {person});
  EXPECT_EQ(plan.planner(), "kinodynamic");
  ASSERT_GT(plan.path_size(), 10);
  EXPECT_EQ(plan.speed_limits_size(), plan.path_size());
  for (const auto& p : plan.path())
    EXPECT_GT(std::hypot(p.x() - 2.5, p.y() - 2.2), 0.25 + 0.3) << p.x() << ", " << p.y();
  // The chapter's own planner, the crowd RRT in its MPC loop rolled out along an A* route, across
  // the warehouse past someone standing on the way.
  v1::MovingBody standing = person;
  standing.mutable_position()->set_x(4.8);
  standing.mutable_position()->set_y(4.8);
  const auto rolled =
      client().ComputePath(0.8, 1, 8.8, 8.8, "kinodynamic", {{"algorithm", 3}, {"time_limit", 10.0}}, {standing});
  ASSERT_GT(rolled.path_size(), 20);
  EXPECT_EQ(rolled.speed_limits_size(), rolled.path_size());
  const auto& end = rolled.path(rolled.path_size() - 1);
  EXPECT_LT(std::hypot(end.x() - 8.8, end.y() - 8.8), 0.3);
  for (const auto& p : rolled.path())
    EXPECT_GT(std::hypot(p.x() - 4.8, p.y() - 4.8), 0.25 + 0.3) << p.x() << ", " << p.y();
  EXPECT_GT(rolled.expansions(), 2000u);
  // A goal next to someone who stands there for good is not reached, and the reason says why.
  ExpectError(
      [&] {
        client().ComputePath(0.8, 1, 3, 2.6, "kinodynamic", {{"algorithm", 3}, {"time_limit", 10.0}}, {person});
      },
      grpc::StatusCode::NOT_FOUND, {"people's space"});
  person.set_radius(-1);
  ExpectError([&] { client().ComputePath(0.8, 1, 3, 2.6, "kinodynamic", {}, {person}); },
              grpc::StatusCode::INVALID_ARGUMENT, {"moving[0].radius"});
  person.set_radius(0.25);
  person.mutable_velocity()->set_x(NAN);
  ExpectError([&] { client().ComputePath(0.8, 1, 3, 2.6, "astar", {}, {person}); }, grpc::StatusCode::INVALID_ARGUMENT,
              {"moving[0].velocity.x"});
}

TEST_F(BadInput, UnknownPlanner) {
  ExpectError([&] { client().ComputePath(0.8, 1, 3, 2.6, "warp_drive"); }, grpc::StatusCode::INVALID_ARGUMENT,
              {"planner", "warp_drive", "astar"});
  ExpectError(
      [&] {
        client().ComputePath(0.8, 1, 3, 2.6, "astar", {{"bogus", 1}});
      },
      grpc::StatusCode::INVALID_ARGUMENT, {"options", "bogus"});
}

TEST_F(BadInput, MissingMalformedAndUnreadableMapFiles) {
  const std::string dir = MakeTempDir();
  ExpectError([&] { client().LoadMap(dir + "/nope.yaml"); }, grpc::StatusCode::NOT_FOUND, {"nope.yaml"});
  ExpectError([&] { client().LoadMap(""); }, grpc::StatusCode::INVALID_ARGUMENT, {"path"});
  std::ofstream(dir + "/broken.yaml") << "image: [oops\n";
  ExpectError([&] { client().LoadMap(dir + "/broken.yaml"); }, grpc::StatusCode::INVALID_ARGUMENT,
              {"broken.yaml", "malformed"});
  std::ofstream(dir + "/bad.pgm") << "GIF89a not a pgm";
  std::ofstream(dir + "/badimg.yaml") << "image: bad.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n";
  ExpectError([&] { client().LoadMap(dir + "/badimg.yaml"); }, grpc::StatusCode::INVALID_ARGUMENT,
              {"bad.pgm", "not a PGM"});
  // The failed loads left the map alone.
  EXPECT_EQ(client().GetMap(true).info().name(), "warehouse");
  EXPECT_EQ(client().GetMap(true).info().version(), 1u);
}

TEST_F(BadInput, NavigateWhileNavigatingIsRejectedOrPreempts) {
  std::atomic<int> outcome{-1};
  std::thread first([&] {
    Client c({stack_->address(), 5.0});
    outcome = c.NavigateTo(8.8, 8.8, std::nullopt, {}, 60.0).outcome();
  });
  for (int i = 0; i < 250 && !client().GetStatus().active(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(client().GetStatus().active());
  ExpectError([&] { client().NavigateTo(3.0, 2.6); }, grpc::StatusCode::FAILED_PRECONDITION,
              {"active", "rejected", "preempt"});
  // With preempt the new goal replaces the old, which ends PREEMPTED.
  v1::NavigateToRequest req;
  req.mutable_goal()->set_x(0.8);
  req.mutable_goal()->set_y(2.0);
  req.set_preempt(true);
  const auto second = client().NavigateTo(req, {}, 60.0);
  first.join();
  EXPECT_EQ(outcome.load(), v1::PREEMPTED);
  EXPECT_EQ(second.outcome(), v1::SUCCEEDED) << second.message();
}

TEST_F(BadInput, LocalisationMethodsCanBeListedSelectedAndStreamed) {
  const auto methods = client().ListMethods();
  ASSERT_EQ(methods.methods_size(), 7);
  EXPECT_EQ(methods.methods(6), "auto");
  EXPECT_EQ(methods.selected(), "amcl");
  ExpectError([&] { client().SelectMethod("gps"); }, grpc::StatusCode::INVALID_ARGUMENT,
              {"method", "gps", "amcl", "auto"});
  client().SelectMethod("odometry");
  EXPECT_EQ(client().GetPose().localizer(), "odometry");
  for (const char* method : {"ekf", "calibration", "histogram"}) {
    client().SelectMethod(method);
    EXPECT_EQ(client().GetPose().localizer(), method);
  }
  client().SelectMethod("auto");  // the arbiter answers with one of the others
  const std::string chosen = client().GetPose().localizer();
  EXPECT_NE(chosen, "auto");
  client().SelectMethod("amcl");
  int poses = 0;
  client().StreamPose(
      20.0, [&](const v1::GetPoseResponse& p) { return ++poses < 5 && p.localizer() == "amcl"; }, 5.0);
  EXPECT_EQ(poses, 5);
  EXPECT_NO_THROW(client().GlobalRelocalize());
  EXPECT_TRUE(std::isfinite(client().GetPose().pose().x()));
}

TEST_F(BadInput, ServesTheMapAndHealth) {
  const auto map = client().GetMap();
  EXPECT_EQ(map.info().width(), 200u);
  EXPECT_EQ(map.cells().size(), 200u * 200u);
  EXPECT_EQ(client().Health(), grpc::health::v1::HealthCheckResponse::SERVING);
  for (const char* service : {"navd.v1.PlanningService", "navd.v1.LocalizationService", "navd.v1.MappingService",
                              "navd.v1.NavigationService"})
    EXPECT_EQ(client().Health(service), grpc::health::v1::HealthCheckResponse::SERVING) << service;
}

}  // namespace
}  // namespace navd::testing
