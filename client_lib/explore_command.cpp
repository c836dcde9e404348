#include "client_lib/explore_command.h"

#include <chrono>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <thread>

#include "client_lib/navctl_text.h"
#include "client_lib/pose_error_meter.h"
#include "client_lib/telemetry.h"
#include "services/common/world.h"
#include "services/mapping/map_coverage.h"

namespace navd::navctl {

namespace {

const char* StateText(v1::ExplorationState s) {
  switch (s) {
    case v1::EXPLORATION_STATE_IDLE: return "idle";
    case v1::EXPLORATION_STATE_EXPLORING: return "exploring";
    case v1::EXPLORATION_STATE_COMPLETE: return "complete";
    case v1::EXPLORATION_STATE_STOPPED: return "stopped";
    case v1::EXPLORATION_STATE_FAILED: return "failed";
    default: return "unknown";
  }
}

const char* MethodText(v1::ExplorationMethod m) {
  switch (m) {
    case v1::EXPLORATION_METHOD_GREEDY: return "greedy";
    case v1::EXPLORATION_METHOD_VFM: return "vfm";
    default: return "frontier";
  }
}

nlohmann::json StatusJson(const v1::ExplorationStatus& s) {
  return {{"state", StateText(s.state())},
          {"method", MethodText(s.method())},
          {"message", s.message()},
          {"explored_area", s.explored_area()},
          {"frontier_cells", s.frontier_cells()},
          {"goals", s.goals()},
          {"goals_given_up", s.goals_given_up()},
          {"elapsed", s.elapsed()},
          {"distance_travelled", s.distance_travelled()},
          {"goal", PoseJson(s.goal())},
          {"slam_nodes", s.mapping().nodes()},
          {"loop_closures", s.mapping().loop_closures()}};
}

void PrintStatus(const v1::ExplorationStatus& s) {
  std::printf(
      "exploration %s (%s): %s; %.1f m2 explored, %u frontier cells, %u goals (%u given up), %.1f s, "
      "%.1f m travelled (estimated), %u SLAM nodes, %u loop closures\n",
      StateText(s.state()), MethodText(s.method()), s.message().c_str(), s.explored_area(), s.frontier_cells(),
      s.goals(), s.goals_given_up(), s.elapsed(), s.distance_travelled(), s.mapping().nodes(),
      s.mapping().loop_closures());
}

}  // namespace

int RunExplore(Client& client, const ExploreOptions& o) {
  if (o.action == "stop") {
    const auto s = client.StopExploration();
    o.json ? (void)std::printf("%s\n", StatusJson(s).dump().c_str()) : PrintStatus(s);
    return 0;
  }
  if (o.action == "status") {
    const auto s = client.GetExplorationStatus();
    o.json ? (void)std::printf("%s\n", StatusJson(s).dump().c_str()) : PrintStatus(s);
    return 0;
  }
  if (o.action != "start") throw std::invalid_argument("explore: action must be start, stop or status");
  if (o.measure && !o.wait) throw std::invalid_argument("explore: --measure needs --wait");

  // Ground truth and navd's estimates (the SLAM poses while exploring), matched by stamp.
  PoseErrorMeter meter;
  MeasuredRun measured;
  if (o.measure)
    measured = StartMeasuring(meter, {o.domain, dds::Network::kLoopback, "navctl-explore", {}, o.dds_security, {}},
                              o.robot_namespace);
  const std::unique_ptr<Telemetry>& telemetry = measured.telemetry;
  const auto& before = measured.before;

  v1::StartExplorationRequest req;
  if (o.method == "greedy") {
    req.set_method(v1::EXPLORATION_METHOD_GREEDY);
  } else if (o.method == "vfm") {
    req.set_method(v1::EXPLORATION_METHOD_VFM);
  } else if (o.method == "frontier") {
    req.set_method(v1::EXPLORATION_METHOD_FRONTIER);
  } else {
    throw std::invalid_argument("explore: --method must be frontier, greedy or vfm");
  }
  req.set_resolution(o.resolution);
  req.set_size(o.size);
  req.set_max_time(o.max_time);
  req.set_planner(o.planner);
  v1::ExplorationStatus s = client.StartExploration(req);
  if (!o.wait) {
    o.json ? (void)std::printf("%s\n", StatusJson(s).dump().c_str()) : PrintStatus(s);
    return 0;
  }
  double last_print = -1e9;
  while (s.state() == v1::EXPLORATION_STATE_EXPLORING) {
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    s = client.GetExplorationStatus();
    if (!o.json && s.elapsed() - last_print >= 10.0) {
      last_print = s.elapsed();
      std::printf("  t=%6.1fs  %7.1f m2 explored  %5u frontier cells  %3u goals  %6.1f m travelled\n", s.elapsed(),
                  s.explored_area(), s.frontier_cells(), s.goals(), s.distance_travelled());
      std::fflush(stdout);
    }
  }
  nlohmann::json j = StatusJson(s);
  if (!o.json) PrintStatus(s);
  if (telemetry) {
    const auto after = telemetry->WaitForSimStatus(5.0);
    if (!after) throw std::runtime_error("--measure: the simulator stopped reporting");
    const World world = o.world.empty() ? DefaultWorld() : LoadWorldOrMapFile(o.world);
    const OccupancyGrid built = ToOccupancyGrid(client.GetMap());
    const mapping::MapCoverage coverage = mapping::CoverageOf(built, world.map, Point2(before.x(), before.y()));
    const double distance = after->distance_travelled() - before.distance_travelled();
    const unsigned collisions = after->collisions() - before.collisions();
    const PoseErrorFigures e = meter.Figures();
    j["truth"] = {{"distance_travelled", distance},         {"collisions", collisions},
                  {"mean_position_error", e.mean_position}, {"max_position_error", e.max_position},
                  {"reachable_mapped", coverage.known},     {"reachable_mapped_free", coverage.known_free}};
    if (!o.json) {
      std::printf(
          "ground truth: %.1f%% of the reachable free space mapped (%.1f%% mapped free), %.1f m driven, "
          "%u collisions, %.1f s; position error mean %.3f m, max %.3f m\n",
          100.0 * coverage.known, 100.0 * coverage.known_free, distance, collisions, s.elapsed(), e.mean_position,
          e.max_position);
    }
  }
  if (o.json) std::printf("%s\n", j.dump().c_str());
  return s.state() == v1::EXPLORATION_STATE_COMPLETE ? 0 : 1;
}

}  // namespace navd::navctl
