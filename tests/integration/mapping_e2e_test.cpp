// Mapping inside navd, end to end: the robot drives the default world's goals while navd builds a
// map from its scans (SLAM), streams the changed regions, publishes rt/map, and saves the result
// as files that load back as the served map. Judged against the world's own map.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <thread>

#include "client_lib/telemetry.h"
#include "services/common/world.h"
#include "tests/support/navd_fixture.h"

namespace navd::testing {
namespace {

// The built map against the truth: of the cells it calls occupied, how many have a true obstacle
// within three cells (15 cm); of the truth's free cells, how many it saw as free. `shift` moves
// the built map first: its frame starts at the localiser's estimate, whose error of a few
// centimetres and a fraction of a degree would shift every wall.
struct MapAgreement {
  double occupied_precision = 0.0;
  double free_coverage = 0.0;
};

MapAgreement Compare(const v1::GetMapResponse& built, const OccupancyGrid& truth, const Pose2& shift = {}) {
  const auto& info = built.info();
  const std::string& cells = built.cells();
  size_t occupied = 0, occupied_right = 0, free_seen = 0;
  std::vector<uint8_t> seen_free(truth.cells().size(), 0);
  for (uint32_t y = 0; y < info.height(); ++y) {
    for (uint32_t x = 0; x < info.width(); ++x) {
      const int8_t v = static_cast<int8_t>(cells[static_cast<size_t>(y) * info.width() + x]);
      if (v < 0) continue;
      const Point2 p = shift * Point2(info.origin().x() + (x + 0.5) * info.resolution(),
                                      info.origin().y() + (y + 0.5) * info.resolution());
      const CellIndex c = truth.CellOf(p);
      if (!truth.Contains(c)) continue;
      if (v >= 65) {
        ++occupied;
        bool near = false;
        for (int dy = -3; dy <= 3 && !near; ++dy)
          for (int dx = -3; dx <= 3 && !near; ++dx)
            near = truth.Contains({c.x + dx, c.y + dy}) && truth.IsOccupied({c.x + dx, c.y + dy});
        occupied_right += near;
      } else if (v < 20 && truth.at(c) == OccupancyGrid::kFree) {
        seen_free[truth.Flat(c)] = 1;
      }
    }
  }
  size_t truth_free = 0;
  for (size_t i = 0; i < truth.cells().size(); ++i) {
    truth_free += truth.cells()[i] == OccupancyGrid::kFree;
    free_seen += seen_free[i];
  }
  return {occupied ? double(occupied_right) / occupied : 0.0, truth_free ? double(free_seen) / truth_free : 0.0};
}

TEST(MappingE2E, SlamWhileDrivingStreamsUpdatesAndSavesAMapThatLoadsBack) {
  StackOptions options;
  options.rate = 10.0;
  NavdStack stack(options);
  const auto telemetry = stack.MakeTelemetry();
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  Client& client = stack.client();

  const v1::MappingStatus started = client.StartMapping(v1::MAPPING_MODE_SLAM, 0.05, 20.0);
  EXPECT_TRUE(started.active());
  EXPECT_EQ(started.info().width(), 400u);
  // A second run while one is active is refused.
  try {
    client.StartMapping();
    ADD_FAILURE() << "no error";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::FAILED_PRECONDITION) << e.what();
  }

  // Changed regions while the robot drives.
  std::atomic<int> updates{0};
  std::atomic<bool> bad_region{false};
  std::thread listener([&] {
    Client own(ClientOptions{stack.address()});
    own.StreamMapUpdates(
        0.5,
        [&](const v1::MapUpdate& u) {
          ++updates;
          if (u.x() + u.width() > u.info().width() || u.y() + u.height() > u.info().height() ||
              u.cells().size() != static_cast<size_t>(u.width()) * u.height())
            bad_region = true;
          return true;
        },
        200.0);
  });

  const World world = DefaultWorld();
  for (const Pose2& goal : world.goals) {
    const v1::NavigationResult result = client.NavigateTo(goal.x, goal.y, std::nullopt, {}, 120.0);
    ASSERT_EQ(result.outcome(), v1::SUCCEEDED) << result.message() << "\n" << stack.Logs();
  }
  const v1::MappingStatus running = client.GetMappingStatus();
  EXPECT_GT(running.scans(), 20u);
  EXPECT_GT(running.nodes(), 10u);
  // rt/map carried the map being built (400 x 400), in nav_msgs/OccupancyGrid layout.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < deadline &&
         (!telemetry->LatestMap() || telemetry->LatestMap()->info().width() != 400u))
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(telemetry->LatestMap());
  EXPECT_EQ(telemetry->LatestMap()->info().width(), 400u);
  EXPECT_EQ(telemetry->LatestMap()->data().size(), 400u * 400u);
  EXPECT_EQ(telemetry->LatestMap()->header().frame_id(), "map");

  const v1::MappingStatus stopped = client.StopMapping();
  EXPECT_FALSE(stopped.active());
  listener.join();
  EXPECT_GT(updates.load(), 3);
  EXPECT_FALSE(bad_region.load());
  try {
    client.StopMapping();
    ADD_FAILURE() << "no error";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::FAILED_PRECONDITION);
  }

  // The map built, in chunks, against the world's map.
  const v1::GetMapResponse built = client.GetMap(false, v1::MAP_SOURCE_MAPPING);
  ASSERT_EQ(built.cells().size(), 400u * 400u);
  // The best small rigid shift about the start (the anchor's error), then the agreement.
  MapAgreement agreement;
  Pose2 best_shift;
  const Pose2 start = world.start;
  for (double dt = -0.04; dt <= 0.0401; dt += 0.01)
    for (double dx = -0.15; dx <= 0.151; dx += 0.05)
      for (double dy = -0.15; dy <= 0.151; dy += 0.05) {
        const Pose2 rotate_about_start = Pose2{start.x + dx, start.y + dy, dt} * Pose2{-start.x, -start.y, 0.0};
        const MapAgreement a = Compare(built, world.map, rotate_about_start);
        if (a.occupied_precision > agreement.occupied_precision) {
          agreement = a;
          best_shift = {dx, dy, dt};
        }
      }
  std::printf("anchor error taken out: (%.2f m, %.2f m, %.2f rad)\n", best_shift.x, best_shift.y, best_shift.theta);
  std::printf("mapped: %.1f%% of occupied cells on a true obstacle, %.1f%% of the free space seen\n",
              100 * agreement.occupied_precision, 100 * agreement.free_coverage);
  EXPECT_GT(agreement.occupied_precision, 0.9);
  EXPECT_GT(agreement.free_coverage, 0.3);

  // Saved atomically as map_server YAML + PGM and as PNG; loaded back as the served map.
  const std::string dir = stack.dir();
  const v1::SaveMapResponse saved =
      client.SaveMap(dir + "/built.yaml", v1::MAP_FORMAT_MAP_SERVER, v1::MAP_SOURCE_MAPPING);
  ASSERT_EQ(saved.files_size(), 2);
  EXPECT_TRUE(std::filesystem::exists(dir + "/built.pgm"));
  client.SaveMap(dir + "/built.png", v1::MAP_FORMAT_PNG, v1::MAP_SOURCE_MAPPING);
  EXPECT_GT(std::filesystem::file_size(dir + "/built.png"), 100u);
  try {
    client.SaveMap("/nonexistent-dir/x.yaml", v1::MAP_FORMAT_MAP_SERVER, v1::MAP_SOURCE_MAPPING);
    ADD_FAILURE() << "no error";
  } catch (const ClientError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir"), std::string::npos) << e.what();
  }
  const v1::MapInfo loaded = client.LoadMap(dir + "/built.yaml");
  EXPECT_EQ(loaded.width(), 400u);
  EXPECT_EQ(client.GetMap(true).info().width(), 400u);
  // Absurd sizes are refused before allocating; the served map stays.
  try {
    client.StartMapping(v1::MAPPING_MODE_KNOWN_POSES, 0.01, 1e5);
    ADD_FAILURE() << "no error";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_NE(std::string(e.what()).find("size"), std::string::npos) << e.what();
  }
  EXPECT_EQ(client.GetMap(true).info().width(), 400u);
}

}  // namespace
}  // namespace navd::testing
