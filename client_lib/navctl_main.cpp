// navctl: the command-line client of navd. One readable line and a non-zero exit on any error.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "client_lib/door_command.h"
#include "client_lib/replay_command.h"
#include "client_lib/explore_command.h"
#include "client_lib/deliver_command.h"
#include "client_lib/follow_command.h"
#include "client_lib/navctl_replies.h"
#include "client_lib/navctl_text.h"
#include "client_lib/navd_client.h"
#include "client_lib/telemetry.h"
#include "services/common/map_store.h"
#include "services/common/movingai_format.h"
#include "services/common/world.h"
#include "services/planning/planner_catalog.h"
#include "services/planning/scenario_benchmark.h"

namespace {

using navd::navctl::ParseTuple;
using navd::navctl::PlanJson;
using navd::navctl::StateText;
using nlohmann::json;

// "--option NAME=VALUE" flags into planner options.
std::map<std::string, double> ParseOptions(const std::vector<std::string>& texts) {
  std::map<std::string, double> out;
  for (const auto& t : texts) {
    const size_t eq = t.find('=');
    char* end = nullptr;
    const double v = eq == std::string::npos ? 0.0 : std::strtod(t.c_str() + eq + 1, &end);
    if (eq == std::string::npos || eq == 0 || end == t.c_str() + eq + 1 || *end != '\0') {
      throw std::invalid_argument("--option '" + t + "' is not NAME=NUMBER");
    }
    out[t.substr(0, eq)] = v;
  }
  return out;
}

// "--person X,Y[,VX,VY]" and "--obstacle X,Y,R[,VX,VY]" flags into moving bodies.
std::vector<navd::planning::MovingBody> ParseMoving(const std::vector<std::string>& people,
                                                    const std::vector<std::string>& obstacles) {
  std::vector<navd::planning::MovingBody> out;
  for (const auto& t : people) {
    const auto v = ParseTuple(t, "--person", 2, 4);
    if (v.size() == 3) throw std::invalid_argument("--person '" + t + "' is not X,Y or X,Y,VX,VY");
    out.push_back({{v[0], v[1]}, {v.size() == 4 ? v[2] : 0.0, v.size() == 4 ? v[3] : 0.0}, 0.25, true});
  }
  for (const auto& t : obstacles) {
    const auto v = ParseTuple(t, "--obstacle", 3, 5);
    if (v.size() == 4) throw std::invalid_argument("--obstacle '" + t + "' is not X,Y,R or X,Y,R,VX,VY");
    out.push_back({{v[0], v[1]}, {v.size() == 5 ? v[3] : 0.0, v.size() == 5 ? v[4] : 0.0}, v[2], false});
  }
  return out;
}

// `navctl plan --map FILE [--scen FILE]`: plans in this process with navd's planning library.
int RunOfflinePlan(const std::string& map_path, const std::string& scen_path, const std::string& from,
                   const std::string& to, std::vector<std::string> planners, bool json_out, double inflation,
                   const std::map<std::string, double>& planner_options,
                   const std::vector<navd::planning::MovingBody>& moving) {
  navd::MapStore maps;
  std::string name;
  const auto snapshot = maps.Set(navd::LoadAnyMapFile(map_path, &name), name);
  navd::planning::PlanningEngineOptions options;
  // MovingAI benchmarks plan for a point robot on 1 m cells: no inflation. Other maps are for
  // navd's robot: its radius plus the daemon's 0.10 m margin.
  const bool movingai = std::filesystem::path(map_path).extension() == ".map";
  options.costmap.inflation_radius = inflation >= 0 ? inflation
                                     : movingai     ? 0.0
                                                    : navd::RobotDescription().radius + 0.10;
  navd::planning::PlanningEngine engine(maps, options);
  navd::planning::RegisterDefaultPlanners(engine);
  if (planners.empty()) {  // every planner but the time-budgeted sampling ones (name them to run them)
    for (const auto& p : engine.Planners())
      if (!p.time_budgeted) planners.push_back(p.name);
  }
  if (scen_path.empty()) {
    if (from.empty() || to.empty()) throw std::invalid_argument("plan --map needs --scen, or --from and --to");
    const auto a = ParseTuple(from, "--from", 2, 2), b = ParseTuple(to, "--to", 2, 2);
    for (const auto& p : planners) {
      const auto r = engine.ComputePath({a[0], a[1]}, {b[0], b[1]}, p, planner_options, {}, {moving, {}});
      if (json_out) {
        std::printf("%s\n", PlanJson(r.planner, r.length, r.planning_time, r.expansions, r.points).dump().c_str());
      } else {
        std::printf("%s: %zu waypoints, length %.4f m, %.3f ms, %lu expansions\n", r.planner.c_str(), r.points.size(),
                    r.length, r.planning_time * 1e3, static_cast<unsigned long>(r.expansions));
      }
    }
    return 0;
  }
  const auto scenarios = navd::LoadMovingAiScenarios(scen_path);
  json reports = json::array();
  bool all_passed = true;
  for (const auto& p : planners) {
    const auto report =
        navd::planning::RunScenarios(engine, snapshot->grid, scenarios, p, [&](size_t done, size_t total) {
          if (!json_out && (done % 50 == 0 || done == total)) {
            std::fprintf(stderr, "\r  %s: %zu/%zu scenarios", p.c_str(), done, total);
            if (done == total) std::fprintf(stderr, "\r\033[K");
          }
        });
    all_passed &= report.passed == report.total;
    if (json_out) {
      reports.push_back({{"planner", report.planner},
                         {"passed", report.passed},
                         {"total", report.total},
                         {"objective", report.Summary().substr(report.Summary().find(' ') + 1)},
                         {"median_ms", report.median_ms},
                         {"p99_ms", report.p99_ms}});
    } else {
      std::printf("%s\n", report.Summary().c_str());
      for (size_t i = 0; i < report.mismatches.size() && i < 5; ++i) {
        const auto& m = report.mismatches[i];
        std::printf("  scenario %zu: expected %.5f, got %.5f %s\n", m.index, m.expected, m.actual, m.error.c_str());
      }
    }
  }
  if (json_out)
    std::printf("%s\n", json{{"map", map_path}, {"scenarios", scenarios.size()}, {"results", reports}}.dump().c_str());
  return all_passed ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"navctl: command-line client of navd"};
  app.require_subcommand(1);
  navd::ClientOptions client_options;
  app.add_option("--server", client_options.server, "navd address HOST:PORT");
  app.add_option("--tls-ca", client_options.tls_ca,
                 "Connect over TLS, trusting navd's certificate if this PEM CA signed it");
  app.add_option("--tls-cert", client_options.tls_cert, "Mutual TLS: this client's PEM certificate (with --tls-key)");
  app.add_option("--tls-key", client_options.tls_key, "Mutual TLS: the PEM private key of --tls-cert");
  app.add_option("--tls-server-name", client_options.tls_server_name,
                 "The name navd's certificate carries, when --server's host is another (an IP address, say)");
  app.add_option("--token", client_options.token, "Bearer token for navd's roles (needs TLS)")->envname("NAVD_TOKEN");
  std::string dds_security;
  app.add_option("--dds-security", dds_security,
                 "DDS Security enclave (scripts/make-keystore's dds/enclaves/navctl) for the commands that use DDS: "
                 "truth, door, replay, follow/explore --measure");
  // NaN slips past CLI11's number checks, so seconds get their own.
  const CLI::Validator seconds(
      [](std::string& s) {
        char* end = nullptr;
        const double v = std::strtod(s.c_str(), &end);
        return std::isfinite(v) && v >= 0 ? std::string() : "must be a finite number of seconds >= 0";
      },
      "SECONDS");
  app.add_option("--deadline", client_options.timeout, "Deadline of each call, seconds")->check(seconds);

  auto* health = app.add_subcommand("health", "Check navd's grpc.health.v1 status");

  auto* plan = app.add_subcommand("plan", "Plan a path on navd, or offline on a map file (--map)");
  std::string from, to, planner, offline_map, scen;
  std::vector<std::string> plan_planners;
  bool json_out = false;
  plan->add_option("--from", from, "Start X,Y (map frame, metres)");
  plan->add_option("--to", to, "Goal X,Y");
  plan->add_option("--planner", plan_planners, "Planner name (see 'planners'); offline batches accept several");
  plan->add_option("--map", offline_map,
                   "Plan offline, without a server, on this map file (MovingAI .map, map_server or world YAML)");
  plan->add_option("--scen", scen, "With --map: run every scenario of this MovingAI .scen file and judge optimality");
  plan->add_flag("--json", json_out, "Print one JSON object");
  std::vector<std::string> option_texts;
  plan->add_option("--option", option_texts, "Planner option NAME=VALUE (see 'planners'), repeatable");
  std::vector<std::string> person_texts, obstacle_texts;
  plan->add_option("--person", person_texts,
                   "A person at X,Y[,VX,VY] (m, m/s) for planners that plan around people (kinodynamic), repeatable");
  plan->add_option("--obstacle", obstacle_texts,
                   "A moving obstacle X,Y,R[,VX,VY] (kinodynamic, convex_grid), repeatable");
  double offline_inflation = -1.0;
  plan->add_option(
      "--inflation", offline_inflation,
      "With --map: obstacle inflation radius, m (default 0 for MovingAI maps, robot radius + 0.10 otherwise)");

  auto* planners = app.add_subcommand("planners", "List planners");
  planners->add_flag("--json", json_out, "Print one JSON object");

  auto* navigate = app.add_subcommand("navigate", "Send the robot to a goal; exit 0 only when reached");
  double timeout = 0;
  bool preempt = false;
  navigate->add_option("--to", to, "Goal X,Y[,THETA]")->required();
  navigate->add_option("--timeout", timeout, "Give up (and cancel) after S seconds")->check(seconds);
  navigate->add_option("--planner", planner, "Planner name");
  navigate->add_flag("--preempt", preempt, "Replace an active goal instead of being rejected");
  navigate->add_flag("--json", json_out, "Print the result as one JSON object");

  auto* follow = app.add_subcommand("follow", "Run a waypoint mission; exit 0 only when it succeeds");
  navd::navctl::FollowOptions follow_options;
  follow->add_option("--waypoints", follow_options.waypoints, "Waypoints X,Y[,THETA];X,Y;... (map frame)");
  follow->add_option("--scenario", follow_options.scenario, "Or: visit the targets of this navsim scenario file");
  follow->add_flag("--cyclic", follow_options.cyclic, "Start over at the first waypoint after the last");
  follow->add_option("--laps", follow_options.laps, "With --cyclic: stop after N laps (default: until cancelled)");
  follow->add_option("--max-distance", follow_options.max_distance, "End (succeeded) after travelling M metres")
      ->check(CLI::NonNegativeNumber);
  follow->add_option("--timeout", follow_options.timeout, "Give up (and cancel) after S seconds")->check(seconds);
  follow->add_option("--planner", follow_options.planner, "Planner name");
  follow->add_flag("--preempt", follow_options.preempt, "Replace an active mission instead of being rejected");
  follow->add_flag("--measure", follow_options.measure,
                   "Judge the run against navsim's ground truth over DDS (distance, time, pose error, collisions)");
  follow->add_option("--domain", follow_options.domain, "With --measure: navsim's DDS domain id")
      ->check(CLI::Range(0, 232));
  follow->add_option("--namespace", follow_options.robot_namespace, "With --measure: the robot's namespace");
  follow->add_flag("--json", follow_options.json, "Print the result as one JSON object");
  auto* deliver = app.add_subcommand(
      "deliver", "Run a delivery mission: navd orders the pickups and dropoffs; exit 0 only when it succeeds");
  navd::navctl::DeliverOptions deliver_options;
  deliver
      ->add_option("--task", deliver_options.tasks,
                   "A task NAME:PICKUP_X,PICKUP_Y:DROPOFF_X,DROPOFF_Y[:PRIORITY] (map frame; higher priority is "
                   "delivered first); repeatable")
      ->required();
  deliver->add_option("--capacity", deliver_options.capacity, "Loads the robot carries at once (default: no limit)");
  deliver->add_flag("--return", deliver_options.return_to_start, "End the round where the robot started");
  deliver->add_flag("--plan-only", deliver_options.plan_only, "Print the schedule; the robot does not move");
  deliver->add_option("--timeout", deliver_options.timeout, "Give up (and cancel) after S seconds")->check(seconds);
  deliver->add_option("--planner", deliver_options.planner, "Planner name");
  deliver->add_flag("--preempt", deliver_options.preempt, "Replace an active mission instead of being rejected");
  deliver->add_flag("--json", deliver_options.json, "Print the schedule and result as one JSON object");
  auto* pause = app.add_subcommand("pause", "Pause the active mission (the robot stops, the mission stays)");
  auto* resume = app.add_subcommand("resume", "Resume the paused mission");

  auto* pose = app.add_subcommand("pose", "Print the pose estimate");
  pose->add_flag("--json", json_out, "Print one JSON object");

  auto* set_pose = app.add_subcommand("set-pose", "Re-anchor the pose estimate");
  std::string pose_text;
  set_pose->add_option("pose", pose_text, "X,Y,THETA")->required();

  auto* relocalize = app.add_subcommand("relocalize", "Forget the pose and search the whole map for it");
  auto* localizers = app.add_subcommand("localizers", "List localisation methods, or select one");
  std::string select_method;
  localizers->add_option("--select", select_method, "Method to answer for the pose (amcl, odometry)");

  auto* cancel = app.add_subcommand("cancel", "Cancel the active navigation");
  auto* status = app.add_subcommand("status", "Print navigation status");
  status->add_flag("--json", json_out, "Print one JSON object");

  auto* zones_cmd = app.add_subcommand("speed-zones", "Print navd's speed zones, or replace them (--set, --clear)");
  std::vector<std::string> zone_specs;
  bool clear_zones = false;
  zones_cmd->add_option("--set", zone_specs, "A zone NAME:X_MIN,Y_MIN,X_MAX,Y_MAX:MAX_SPEED (metres, m/s); repeatable");
  zones_cmd->add_flag("--clear", clear_zones, "Remove every zone")->excludes("--set");
  zones_cmd->add_flag("--json", json_out, "Print one JSON object");

  auto* map = app.add_subcommand("map", "Print the map's metadata");
  map->add_flag("--json", json_out, "Print one JSON object");
  auto* load_map = app.add_subcommand("load-map", "Load a map file the server can read");
  std::string map_path;
  load_map->add_option("path", map_path, "map_server YAML or world YAML")->required();
  auto* save_map = app.add_subcommand("save-map", "Save the served map (or the one being built) on the server");
  std::string save_path, save_format = "yaml";
  bool save_built = false;
  save_map->add_option("path", save_path, "Output path: map_server YAML (the PGM goes beside it) or PNG")->required();
  save_map->add_option("--format", save_format, "yaml (map_server YAML + PGM) or png")
      ->check(CLI::IsMember({"yaml", "png"}));
  save_map->add_flag("--built", save_built, "Save the map of the current (or last) mapping run");
  auto* mapping_cmd = app.add_subcommand("mapping", "Build a map from the robot's scans: start, stop, status");
  std::string mapping_action, mapping_mode = "slam";
  double mapping_resolution = 0.0, mapping_size = 0.0;
  bool mapping_serve = false;
  mapping_cmd->add_option("action", mapping_action, "start, stop or status")
      ->required()
      ->check(CLI::IsMember({"start", "stop", "status"}));
  mapping_cmd
      ->add_option("--mode", mapping_mode, "start: slam (odometry + scan matching + loop closure) or known_poses")
      ->check(CLI::IsMember({"slam", "known_poses"}));
  mapping_cmd->add_option("--resolution", mapping_resolution, "start: metres per cell (default 0.05)");
  mapping_cmd->add_option("--size", mapping_size,
                          "start: metres, side of the square mapped around the robot (default 60)");
  mapping_cmd->add_flag("--serve", mapping_serve, "stop: make the built map the one navd plans and localises on");
  mapping_cmd->add_flag("--json", json_out, "Print one JSON object");

  auto* explore =
      app.add_subcommand("explore", "Explore from where the robot stands, building the map: start, stop, status");
  navd::navctl::ExploreOptions explore_options;
  explore->add_option("action", explore_options.action, "start, stop or status")
      ->required()
      ->check(CLI::IsMember({"start", "stop", "status"}));
  explore
      ->add_option("--method", explore_options.method,
                   "start: frontier (Yamauchi), greedy (seed 002) or vfm (book ch. 4 Voronoi Fast Marching)")
      ->check(CLI::IsMember({"frontier", "greedy", "vfm"}));
  explore->add_option("--resolution", explore_options.resolution, "start: metres per cell (default 0.05)")
      ->check(CLI::NonNegativeNumber);
  explore
      ->add_option("--size", explore_options.size,
                   "start: metres, side of the square mapped around the robot (default 60)")
      ->check(CLI::NonNegativeNumber);
  explore->add_option("--max-time", explore_options.max_time, "start: give up after this many seconds (0: never)")
      ->check(seconds);
  explore->add_option("--planner", explore_options.planner, "start: planner of each leg");
  explore->add_flag("--wait", explore_options.wait,
                    "start: follow the exploration to its end; exit 0 only when complete");
  explore->add_flag("--measure", explore_options.measure,
                    "with --wait: judge against navsim (collisions, distance) and the world (share mapped)");
  explore->add_option("--world", explore_options.world,
                      "with --measure: navsim's world file (default: the embedded one)");
  explore->add_option("--domain", explore_options.domain, "with --measure: navsim's DDS domain id")
      ->check(CLI::Range(0, 232));
  explore->add_option("--namespace", explore_options.robot_namespace, "with --measure: robot namespace");
  explore->add_flag("--json", explore_options.json, "Print one JSON object");

  auto* truth = app.add_subcommand("truth", "Print the simulator's ground truth (DDS)");
  int domain = 0;
  std::string ns;
  double wait = 5.0;
  truth->add_option("--domain", domain, "DDS domain id")->check(CLI::Range(0, 232));
  truth->add_option("--namespace", ns, "Robot namespace");
  truth->add_option("--wait", wait, "Seconds to wait for a sample")->check(seconds);
  truth->add_flag("--json", json_out, "Print one JSON object");
  std::string truth_goal;
  truth->add_option("--to", truth_goal, "Also print the true distance to this X,Y");

  auto* door = app.add_subcommand("door", "Open or close a simulator door by name (DDS)");
  navd::navctl::DoorOptions door_options;
  std::string door_action;
  door->add_option("name", door_options.name, "The door's name in the scenario")->required();
  door->add_option("action", door_action, "open or close")->required()->check(CLI::IsMember({"open", "close"}));
  door->add_option("--domain", door_options.domain, "DDS domain id of navsim")->check(CLI::Range(0, 232));
  door->add_option("--wait", door_options.wait, "Seconds to wait for navsim to do it")->check(seconds);
  door->add_flag("--json", door_options.json, "Print one JSON object");

  auto* replay =
      app.add_subcommand("replay", "Play a CARMEN log over DDS like a robot while navd localises; judge its poses");
  navd::navctl::ReplayOptions replay_options;
  replay->add_option("--log", replay_options.log, "CARMEN log (.log or .log.gz)")->required();
  replay->add_option("--rate", replay_options.rate, "Log seconds per wall second")->check(CLI::Range(0.01, 10000.0));
  replay->add_option("--domain", replay_options.domain, "navd's DDS domain id")->check(CLI::Range(0, 232));
  replay->add_option("--namespace", replay_options.robot_namespace, "Robot namespace of navd's topics");
  replay->add_option("--server", replay_options.server, "navd's gRPC address, to set the first pose (\"\" to skip)");
  replay
      ->add_option("--odometry", replay_options.odometry,
                   "noisy (the log's corrected poses corrupted by --odom-noise, seeded: the evaluation protocol, "
                   "default) or log (the odometry the log holds: ODOM lines, else FLASER's odometry fields)")
      ->check(CLI::IsMember({"noisy", "log"}));
  replay->add_option("--pairing", replay_options.pairing,
                     "with --odometry log: how each scan takes the ODOM lines next to it: auto (as consecutive scans "
                     "matched against each other agree, default), stamp, or a share of the way from the line before "
                     "the scan (0) to the line after it (1), by stamp across a gap of over 1 s or where scans share "
                     "their two lines");
  replay->add_option("--odom-noise", replay_options.odom_noise,
                     "T,R: relative translation noise, rad of heading noise per metre; T,R,S,D also errs the same "
                     "way every step: translation scaled by 1 + S, heading drifting D rad per metre");
  replay->add_option("--seed", replay_options.seed, "Seed of the odometry noise");
  replay->add_option("--max-scans", replay_options.max_scans, "Replay only the first N scans")
      ->check(CLI::NonNegativeNumber);
  replay->add_option("--range-max", replay_options.range_max, "Beams are cut at this range, metres")
      ->check(CLI::Range(0.1, 100.0));
  replay
      ->add_option("--far-range-max", replay_options.far_range_max,
                   "... or at this range in a scan with too few echoes within --range-max (an open hall), metres")
      ->check(CLI::Range(0.1, 100.0));
  replay->add_option("--out", replay_options.out, "Write navd's poses as TUM (t x y z qx qy qz qw)");
  replay->add_flag("--strict", replay_options.strict, "Stop at the first malformed log line");
  replay->add_option("--wait", replay_options.wait, "Seconds to wait for navd on DDS")->check(seconds);
  std::string kidnap, slip;
  replay->add_option("--kidnap", kidnap,
                     "T,DX,DY: at T s of log time the robot is carried DX,DY metres (its frame): the scans skip to "
                     "where the log has it nearest that point, its odometry stands still; reports when navd declared "
                     "itself lost and when it was back within 0.1 m");
  replay->add_option("--slip", slip,
                     "T,DX,DY: at T s of log time the odometry slips DX,DY metres (its frame) over 1 s while the scans "
                     "go on; reports as --kidnap does");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  try {
    if (replay->parsed()) {
      if (replay->get_option("--pairing")->count() > 0 && replay_options.odometry != "log")
        throw std::invalid_argument("--pairing is for --odometry log (the ODOM lines it pairs with the scans)");
      if (!kidnap.empty())
        navd::navctl::ParseDisturbance("--kidnap", kidnap, navd::navctl::Disturbance::kKidnap, &replay_options);
      if (!slip.empty())
        navd::navctl::ParseDisturbance("--slip", slip, navd::navctl::Disturbance::kSlip, &replay_options);
      replay_options.dds_security = dds_security;
      return navd::navctl::RunReplay(replay_options);
    }
    if (door->parsed()) {
      door_options.close = door_action == "close";
      door_options.dds_security = dds_security;
      return navd::navctl::RunDoor(door_options);
    }
    if (truth->parsed()) {
      navd::TelemetryOptions topts;
      topts.dds.domain = domain;
      topts.dds.name = "navctl";
      topts.dds.security_enclave = dds_security;
      topts.robot_namespace = ns;
      navd::Telemetry telemetry(topts);
      const auto s = telemetry.WaitForSimStatus(wait);
      if (!s)
        throw std::runtime_error("no simulator status on DDS domain " + std::to_string(domain) + " within " +
                                 std::to_string(wait) + " s");
      std::optional<double> error;
      if (!truth_goal.empty()) {
        const auto g = ParseTuple(truth_goal, "--to", 2, 3);
        error = std::hypot(s->x() - g[0], s->y() - g[1]);
      }
      if (json_out) {
        json j{{"x", s->x()},
               {"y", s->y()},
               {"theta", s->theta()},
               {"collisions", s->collisions()},
               {"in_collision", s->in_collision()},
               {"distance_travelled", s->distance_travelled()},
               {"sim_time", s->header().stamp().sec() + s->header().stamp().nanosec() * 1e-9}};
        if (error) j["error"] = *error;
        std::printf("%s\n", j.dump().c_str());
      } else {
        std::printf("true pose (%.3f, %.3f, %.3f)  collisions %u  travelled %.2f m", s->x(), s->y(), s->theta(),
                    s->collisions(), s->distance_travelled());
        if (error) std::printf("  error to goal %.3f m", *error);
        std::printf("\n");
      }
      return 0;
    }

    if (plan->parsed() && !offline_map.empty()) {
      return RunOfflinePlan(offline_map, scen, from, to, plan_planners, json_out, offline_inflation,
                            ParseOptions(option_texts), ParseMoving(person_texts, obstacle_texts));
    }
    if (plan->parsed()) {
      if (from.empty() || to.empty()) throw std::invalid_argument("plan needs --from and --to (or --map with --scen)");
      if (!scen.empty()) throw std::invalid_argument("--scen needs --map");
      if (plan_planners.size() > 1) throw std::invalid_argument("plan on a server takes one --planner");
      planner = plan_planners.empty() ? "" : plan_planners[0];
    }

    navd::Client client(client_options);
    if (health->parsed()) {
      const auto st = client.Health();
      std::printf("%s\n", grpc::health::v1::HealthCheckResponse::ServingStatus_Name(st).c_str());
      return st == grpc::health::v1::HealthCheckResponse::SERVING ? 0 : 1;
    }
    if (plan->parsed()) {
      const auto a = ParseTuple(from, "--from", 2, 2), b = ParseTuple(to, "--to", 2, 2);
      std::vector<navd::v1::MovingBody> moving;
      for (const auto& m : ParseMoving(person_texts, obstacle_texts)) {
        navd::v1::MovingBody& b = moving.emplace_back();
        b.mutable_position()->set_x(m.position.x());
        b.mutable_position()->set_y(m.position.y());
        b.mutable_velocity()->set_x(m.velocity.x());
        b.mutable_velocity()->set_y(m.velocity.y());
        b.set_radius(m.radius);
        b.set_person(m.person);
      }
      const auto r = client.ComputePath(a[0], a[1], b[0], b[1], planner, ParseOptions(option_texts), moving);
      navd::navctl::PrintPath(r, json_out);
      return 0;
    }
    if (planners->parsed()) {
      navd::navctl::PrintPlanners(client.ListPlanners(), json_out);
      return 0;
    }
    if (navigate->parsed()) {
      const auto g = ParseTuple(to, "--to", 2, 3);
      navd::v1::NavigateToRequest req;
      req.mutable_goal()->set_x(g[0]);
      req.mutable_goal()->set_y(g[1]);
      if (g.size() == 3) {
        req.mutable_goal()->set_theta(g[2]);
        req.set_use_goal_heading(true);
      }
      req.set_planner(planner);
      req.set_preempt(preempt);
      int last_tenth = -1;
      const auto result = client.NavigateTo(
          req,
          [&](const navd::v1::NavigationFeedback& f) {
            // One progress line per second of feedback (feedback arrives at ~10 Hz).
            const int tenth = static_cast<int>(f.stamp().sec());
            if (json_out || tenth == last_tenth) return;
            last_tenth = tenth;
            std::printf("  t=%6.1fs  %-14s pose (%.2f, %.2f, %.2f)  %.2f m to go\n",
                        f.stamp().sec() + f.stamp().nanosec() * 1e-9, StateText(f.state()), f.pose().x(), f.pose().y(),
                        f.pose().theta(), f.distance_remaining());
            std::fflush(stdout);
          },
          timeout);
      navd::navctl::PrintNavigationResult(result, json_out);
      return result.outcome() == navd::v1::SUCCEEDED ? 0 : 1;
    }
    if (pose->parsed()) {
      const auto r = client.GetPose();
      navd::navctl::PrintPose(r, json_out);
      return 0;
    }
    if (set_pose->parsed()) {
      const auto p = ParseTuple(pose_text, "pose", 3, 3);
      client.SetPose(p[0], p[1], p[2]);
      std::printf("pose set to (%.3f, %.3f, %.3f)\n", p[0], p[1], p[2]);
      return 0;
    }
    if (relocalize->parsed()) {
      client.GlobalRelocalize();
      std::printf("relocalising: the estimate settles as the robot moves\n");
      return 0;
    }
    if (localizers->parsed()) {
      if (!select_method.empty()) client.SelectMethod(select_method);
      const auto m = client.ListMethods();
      for (const auto& name : m.methods())
        std::printf("%s%s\n", name.c_str(), name == m.selected() ? " (selected)" : "");
      return 0;
    }
    follow_options.dds_security = explore_options.dds_security = dds_security;
    if (follow->parsed()) return navd::navctl::RunFollow(client, follow_options);
    if (deliver->parsed()) return navd::navctl::RunDeliver(client, deliver_options);
    if (explore->parsed()) return navd::navctl::RunExplore(client, explore_options);
    if (pause->parsed()) {
      client.Pause();
      std::printf("paused\n");
      return 0;
    }
    if (resume->parsed()) {
      client.Resume();
      std::printf("resumed\n");
      return 0;
    }
    if (cancel->parsed()) {
      std::printf("%s\n", client.Cancel() ? "cancelled the active goal" : "no goal was active");
      return 0;
    }
    if (status->parsed()) {
      const auto s = client.GetStatus();
      navd::navctl::PrintStatus(s, json_out);
      return 0;
    }
    if (zones_cmd->parsed()) {
      navd::v1::SpeedZones zones;
      if (!zone_specs.empty() || clear_zones) {
        zones = client.SetSpeedZones(navd::navctl::ParseSpeedZones(zone_specs));
      } else {
        zones = client.GetSpeedZones();
      }
      navd::navctl::PrintSpeedZones(zones, json_out);
      return 0;
    }
    if (map->parsed()) {
      const auto m = client.GetMap(true).info();
      navd::navctl::PrintMapInfo(m, json_out);
      return 0;
    }
    if (save_map->parsed()) {
      const auto r = client.SaveMap(std::filesystem::absolute(save_path).string(),
                                    save_format == "png" ? navd::v1::MAP_FORMAT_PNG : navd::v1::MAP_FORMAT_MAP_SERVER,
                                    save_built ? navd::v1::MAP_SOURCE_MAPPING : navd::v1::MAP_SOURCE_SERVED);
      for (const auto& f : r.files()) std::printf("wrote %s\n", f.c_str());
      return 0;
    }
    if (mapping_cmd->parsed()) {
      navd::v1::MappingStatus st;
      if (mapping_action == "start") {
        st = client.StartMapping(
            mapping_mode == "slam" ? navd::v1::MAPPING_MODE_SLAM : navd::v1::MAPPING_MODE_KNOWN_POSES,
            mapping_resolution, mapping_size);
      } else if (mapping_action == "stop") {
        st = client.StopMapping(mapping_serve);
      } else {
        st = client.GetMappingStatus();
      }
      navd::navctl::PrintMappingStatus(st, json_out);
      return 0;
    }
    if (load_map->parsed()) {
      // navd resolves paths in its own working directory; send ours, absolute.
      const auto m = client.LoadMap(std::filesystem::absolute(map_path).string());
      std::printf("loaded map '%s': %ux%u cells at %.3f m\n", m.name().c_str(), m.width(), m.height(), m.resolution());
      return 0;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navctl: %s\n", e.what());
    return 1;
  }
  return 1;
}
