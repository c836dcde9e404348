// navctl: the command-line client of navd. One readable line and a non-zero exit on any error.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
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

// What every subcommand shares: how to reach navd (gRPC) and the DDS enclave of the commands
// that talk DDS.
struct Globals {
  navd::ClientOptions client;
  std::string dds_security;
};

// A subcommand and what it does once the command line parsed: returns navctl's exit code, throws
// for one readable line.
struct Command {
  CLI::App* sub;
  std::function<int()> run;
};

// NaN slips past CLI11's number checks, so seconds get their own.
const CLI::Validator& Seconds() {
  static const CLI::Validator seconds(
      [](std::string& s) {
        char* end = nullptr;
        const double v = std::strtod(s.c_str(), &end);
        return std::isfinite(v) && v >= 0 ? std::string() : "must be a finite number of seconds >= 0";
      },
      "SECONDS");
  return seconds;
}

// A call to navd with no options but --json, printed by `print`.
Command AddQuery(CLI::App& app, const Globals& g, const char* name, const char* description,
                 std::function<void(navd::Client&, bool json)> print) {
  auto json_out = std::make_shared<bool>(false);
  auto* sub = app.add_subcommand(name, description);
  sub->add_flag("--json", *json_out, "Print one JSON object");
  return {sub, [&g, json_out, print = std::move(print)] {
            navd::Client client(g.client);
            print(client, *json_out);
            return 0;
          }};
}

// A call to navd with no options at all, which says in one line what it did.
Command AddAction(CLI::App& app, const Globals& g, const char* name, const char* description,
                  std::function<void(navd::Client&)> act) {
  auto* sub = app.add_subcommand(name, description);
  return {sub, [&g, act = std::move(act)] {
            navd::Client client(g.client);
            act(client);
            return 0;
          }};
}

Command AddHealth(CLI::App& app, const Globals& g) {
  auto* sub = app.add_subcommand("health", "Check navd's grpc.health.v1 status");
  return {sub, [&g] {
            navd::Client client(g.client);
            const auto st = client.Health();
            std::printf("%s\n", grpc::health::v1::HealthCheckResponse::ServingStatus_Name(st).c_str());
            return st == grpc::health::v1::HealthCheckResponse::SERVING ? 0 : 1;
          }};
}

Command AddPlan(CLI::App& app, const Globals& g) {
  struct Args {
    std::string from, to, offline_map, scen;
    std::vector<std::string> planners, option_texts, person_texts, obstacle_texts;
    bool json = false;
    double offline_inflation = -1.0;
  };
  auto a = std::make_shared<Args>();
  auto* plan = app.add_subcommand("plan", "Plan a path on navd, or offline on a map file (--map)");
  plan->add_option("--from", a->from, "Start X,Y (map frame, metres)");
  plan->add_option("--to", a->to, "Goal X,Y");
  plan->add_option("--planner", a->planners, "Planner name (see 'planners'); offline batches accept several");
  plan->add_option("--map", a->offline_map,
                   "Plan offline, without a server, on this map file (MovingAI .map, map_server or world YAML)");
  plan->add_option("--scen", a->scen,
                   "With --map: run every scenario of this MovingAI .scen file and judge optimality");
  plan->add_flag("--json", a->json, "Print one JSON object");
  plan->add_option("--option", a->option_texts, "Planner option NAME=VALUE (see 'planners'), repeatable");
  plan->add_option("--person", a->person_texts,
                   "A person at X,Y[,VX,VY] (m, m/s) for planners that plan around people (kinodynamic), repeatable");
  plan->add_option("--obstacle", a->obstacle_texts,
                   "A moving obstacle X,Y,R[,VX,VY] (kinodynamic, convex_grid), repeatable");
  plan->add_option(
      "--inflation", a->offline_inflation,
      "With --map: obstacle inflation radius, m (default 0 for MovingAI maps, robot radius + 0.10 otherwise)");
  return {plan, [&g, a] {
            if (!a->offline_map.empty()) {
              return RunOfflinePlan(a->offline_map, a->scen, a->from, a->to, a->planners, a->json, a->offline_inflation,
                                    ParseOptions(a->option_texts), ParseMoving(a->person_texts, a->obstacle_texts));
            }
            if (a->from.empty() || a->to.empty())
              throw std::invalid_argument("plan needs --from and --to (or --map with --scen)");
            if (!a->scen.empty()) throw std::invalid_argument("--scen needs --map");
            if (a->planners.size() > 1) throw std::invalid_argument("plan on a server takes one --planner");
            const std::string planner = a->planners.empty() ? "" : a->planners[0];
            navd::Client client(g.client);
            const auto from = ParseTuple(a->from, "--from", 2, 2), to = ParseTuple(a->to, "--to", 2, 2);
            std::vector<navd::v1::MovingBody> moving;
            for (const auto& m : ParseMoving(a->person_texts, a->obstacle_texts)) {
              navd::v1::MovingBody& b = moving.emplace_back();
              b.mutable_position()->set_x(m.position.x());
              b.mutable_position()->set_y(m.position.y());
              b.mutable_velocity()->set_x(m.velocity.x());
              b.mutable_velocity()->set_y(m.velocity.y());
              b.set_radius(m.radius);
              b.set_person(m.person);
            }
            const auto r =
                client.ComputePath(from[0], from[1], to[0], to[1], planner, ParseOptions(a->option_texts), moving);
            navd::navctl::PrintPath(r, a->json);
            return 0;
          }};
}

Command AddNavigate(CLI::App& app, const Globals& g) {
  struct Args {
    std::string to, planner;
    double timeout = 0;
    bool preempt = false, json = false;
  };
  auto a = std::make_shared<Args>();
  auto* navigate = app.add_subcommand("navigate", "Send the robot to a goal; exit 0 only when reached");
  navigate->add_option("--to", a->to, "Goal X,Y[,THETA]")->required();
  navigate->add_option("--timeout", a->timeout, "Give up (and cancel) after S seconds")->check(Seconds());
  navigate->add_option("--planner", a->planner, "Planner name");
  navigate->add_flag("--preempt", a->preempt, "Replace an active goal instead of being rejected");
  navigate->add_flag("--json", a->json, "Print the result as one JSON object");
  return {navigate, [&g, a] {
            const auto goal = ParseTuple(a->to, "--to", 2, 3);
            navd::Client client(g.client);
            navd::v1::NavigateToRequest req;
            req.mutable_goal()->set_x(goal[0]);
            req.mutable_goal()->set_y(goal[1]);
            if (goal.size() == 3) {
              req.mutable_goal()->set_theta(goal[2]);
              req.set_use_goal_heading(true);
            }
            req.set_planner(a->planner);
            req.set_preempt(a->preempt);
            int last_second = -1;
            const bool json_out = a->json;
            const auto result = client.NavigateTo(
                req,
                [&](const navd::v1::NavigationFeedback& f) {
                  // One progress line per second of feedback (feedback arrives at ~10 Hz).
                  const int second = static_cast<int>(f.stamp().sec());
                  if (json_out || second == last_second) return;
                  last_second = second;
                  std::printf("  t=%6.1fs  %-14s pose (%.2f, %.2f, %.2f)  %.2f m to go\n",
                              f.stamp().sec() + f.stamp().nanosec() * 1e-9, StateText(f.state()), f.pose().x(),
                              f.pose().y(), f.pose().theta(), f.distance_remaining());
                  std::fflush(stdout);
                },
                a->timeout);
            navd::navctl::PrintNavigationResult(result, a->json);
            return result.outcome() == navd::v1::SUCCEEDED ? 0 : 1;
          }};
}

Command AddFollow(CLI::App& app, const Globals& g) {
  auto o = std::make_shared<navd::navctl::FollowOptions>();
  auto* follow = app.add_subcommand("follow", "Run a waypoint mission; exit 0 only when it succeeds");
  follow->add_option("--waypoints", o->waypoints, "Waypoints X,Y[,THETA];X,Y;... (map frame)");
  follow->add_option("--scenario", o->scenario, "Or: visit the targets of this navsim scenario file");
  follow->add_flag("--cyclic", o->cyclic, "Start over at the first waypoint after the last");
  follow->add_option("--laps", o->laps, "With --cyclic: stop after N laps (default: until cancelled)");
  follow->add_option("--max-distance", o->max_distance, "End (succeeded) after travelling M metres")
      ->check(CLI::NonNegativeNumber);
  follow->add_option("--timeout", o->timeout, "Give up (and cancel) after S seconds")->check(Seconds());
  follow->add_option("--planner", o->planner, "Planner name");
  follow->add_flag("--preempt", o->preempt, "Replace an active mission instead of being rejected");
  follow->add_flag("--measure", o->measure,
                   "Judge the run against navsim's ground truth over DDS (distance, time, pose error, collisions)");
  follow->add_option("--domain", o->domain, "With --measure: navsim's DDS domain id")->check(CLI::Range(0, 232));
  follow->add_option("--namespace", o->robot_namespace, "With --measure: the robot's namespace");
  follow->add_flag("--json", o->json, "Print the result as one JSON object");
  return {follow, [&g, o] {
            o->dds_security = g.dds_security;
            navd::Client client(g.client);
            return navd::navctl::RunFollow(client, *o);
          }};
}

Command AddDeliver(CLI::App& app, const Globals& g) {
  auto o = std::make_shared<navd::navctl::DeliverOptions>();
  auto* deliver = app.add_subcommand(
      "deliver", "Run a delivery mission: navd orders the pickups and dropoffs; exit 0 only when it succeeds");
  deliver
      ->add_option("--task", o->tasks,
                   "A task NAME:PICKUP_X,PICKUP_Y:DROPOFF_X,DROPOFF_Y[:PRIORITY] (map frame; higher priority is "
                   "delivered first); repeatable")
      ->required();
  deliver->add_option("--capacity", o->capacity, "Loads the robot carries at once (default: no limit)");
  deliver->add_flag("--return", o->return_to_start, "End the round where the robot started");
  deliver->add_flag("--plan-only", o->plan_only, "Print the schedule; the robot does not move");
  deliver->add_option("--timeout", o->timeout, "Give up (and cancel) after S seconds")->check(Seconds());
  deliver->add_option("--planner", o->planner, "Planner name");
  deliver->add_flag("--preempt", o->preempt, "Replace an active mission instead of being rejected");
  deliver->add_flag("--json", o->json, "Print the schedule and result as one JSON object");
  return {deliver, [&g, o] {
            navd::Client client(g.client);
            return navd::navctl::RunDeliver(client, *o);
          }};
}

Command AddSetPose(CLI::App& app, const Globals& g) {
  auto pose_text = std::make_shared<std::string>();
  auto* set_pose = app.add_subcommand("set-pose", "Re-anchor the pose estimate");
  set_pose->add_option("pose", *pose_text, "X,Y,THETA")->required();
  return {set_pose, [&g, pose_text] {
            const auto p = ParseTuple(*pose_text, "pose", 3, 3);
            navd::Client client(g.client);
            client.SetPose(p[0], p[1], p[2]);
            std::printf("pose set to (%.3f, %.3f, %.3f)\n", p[0], p[1], p[2]);
            return 0;
          }};
}

Command AddLocalizers(CLI::App& app, const Globals& g) {
  auto select_method = std::make_shared<std::string>();
  auto* localizers = app.add_subcommand("localizers", "List localisation methods, or select one");
  localizers->add_option("--select", *select_method, "Method to answer for the pose (amcl, odometry)");
  return {localizers, [&g, select_method] {
            navd::Client client(g.client);
            if (!select_method->empty()) client.SelectMethod(*select_method);
            const auto m = client.ListMethods();
            for (const auto& name : m.methods())
              std::printf("%s%s\n", name.c_str(), name == m.selected() ? " (selected)" : "");
            return 0;
          }};
}

Command AddSpeedZones(CLI::App& app, const Globals& g) {
  struct Args {
    std::vector<std::string> specs;
    bool clear = false, json = false;
  };
  auto a = std::make_shared<Args>();
  auto* zones = app.add_subcommand("speed-zones", "Print navd's speed zones, or replace them (--set, --clear)");
  zones->add_option("--set", a->specs, "A zone NAME:X_MIN,Y_MIN,X_MAX,Y_MAX:MAX_SPEED (metres, m/s); repeatable");
  zones->add_flag("--clear", a->clear, "Remove every zone")->excludes("--set");
  zones->add_flag("--json", a->json, "Print one JSON object");
  return {zones, [&g, a] {
            navd::Client client(g.client);
            const navd::v1::SpeedZones set = a->specs.empty() && !a->clear
                                                 ? client.GetSpeedZones()
                                                 : client.SetSpeedZones(navd::navctl::ParseSpeedZones(a->specs));
            navd::navctl::PrintSpeedZones(set, a->json);
            return 0;
          }};
}

Command AddLoadMap(CLI::App& app, const Globals& g) {
  auto path = std::make_shared<std::string>();
  auto* load_map = app.add_subcommand("load-map", "Load a map file the server can read");
  load_map->add_option("path", *path, "map_server YAML or world YAML")->required();
  return {load_map, [&g, path] {
            navd::Client client(g.client);
            // navd resolves paths in its own working directory; send ours, absolute.
            const auto m = client.LoadMap(std::filesystem::absolute(*path).string());
            std::printf("loaded map '%s': %ux%u cells at %.3f m\n", m.name().c_str(), m.width(), m.height(),
                        m.resolution());
            return 0;
          }};
}

Command AddSaveMap(CLI::App& app, const Globals& g) {
  struct Args {
    std::string path, format = "yaml";
    bool built = false;
  };
  auto a = std::make_shared<Args>();
  auto* save_map = app.add_subcommand("save-map", "Save the served map (or the one being built) on the server");
  save_map->add_option("path", a->path, "Output path: map_server YAML (the PGM goes beside it) or PNG")->required();
  save_map->add_option("--format", a->format, "yaml (map_server YAML + PGM) or png")
      ->check(CLI::IsMember({"yaml", "png"}));
  save_map->add_flag("--built", a->built, "Save the map of the current (or last) mapping run");
  return {save_map, [&g, a] {
            navd::Client client(g.client);
            const auto r =
                client.SaveMap(std::filesystem::absolute(a->path).string(),
                               a->format == "png" ? navd::v1::MAP_FORMAT_PNG : navd::v1::MAP_FORMAT_MAP_SERVER,
                               a->built ? navd::v1::MAP_SOURCE_MAPPING : navd::v1::MAP_SOURCE_SERVED);
            for (const auto& f : r.files()) std::printf("wrote %s\n", f.c_str());
            return 0;
          }};
}

Command AddMapping(CLI::App& app, const Globals& g) {
  struct Args {
    std::string action, mode = "slam";
    double resolution = 0.0, size = 0.0;
    bool serve = false, json = false;
  };
  auto a = std::make_shared<Args>();
  auto* mapping = app.add_subcommand("mapping", "Build a map from the robot's scans: start, stop, status");
  mapping->add_option("action", a->action, "start, stop or status")
      ->required()
      ->check(CLI::IsMember({"start", "stop", "status"}));
  mapping->add_option("--mode", a->mode, "start: slam (odometry + scan matching + loop closure) or known_poses")
      ->check(CLI::IsMember({"slam", "known_poses"}));
  mapping->add_option("--resolution", a->resolution, "start: metres per cell (default 0.05)");
  mapping->add_option("--size", a->size, "start: metres, side of the square mapped around the robot (default 60)");
  mapping->add_flag("--serve", a->serve, "stop: make the built map the one navd plans and localises on");
  mapping->add_flag("--json", a->json, "Print one JSON object");
  return {mapping, [&g, a] {
            navd::Client client(g.client);
            navd::v1::MappingStatus st;
            if (a->action == "start") {
              st = client.StartMapping(
                  a->mode == "slam" ? navd::v1::MAPPING_MODE_SLAM : navd::v1::MAPPING_MODE_KNOWN_POSES, a->resolution,
                  a->size);
            } else if (a->action == "stop") {
              st = client.StopMapping(a->serve);
            } else {
              st = client.GetMappingStatus();
            }
            navd::navctl::PrintMappingStatus(st, a->json);
            return 0;
          }};
}

Command AddExplore(CLI::App& app, const Globals& g) {
  auto o = std::make_shared<navd::navctl::ExploreOptions>();
  auto* explore =
      app.add_subcommand("explore", "Explore from where the robot stands, building the map: start, stop, status");
  explore->add_option("action", o->action, "start, stop or status")
      ->required()
      ->check(CLI::IsMember({"start", "stop", "status"}));
  explore
      ->add_option("--method", o->method,
                   "start: frontier (Yamauchi), greedy (seed 002) or vfm (book ch. 4 Voronoi Fast Marching)")
      ->check(CLI::IsMember({"frontier", "greedy", "vfm"}));
  explore->add_option("--resolution", o->resolution, "start: metres per cell (default 0.05)")
      ->check(CLI::NonNegativeNumber);
  explore->add_option("--size", o->size, "start: metres, side of the square mapped around the robot (default 60)")
      ->check(CLI::NonNegativeNumber);
  explore->add_option("--max-time", o->max_time, "start: give up after this many seconds (0: never)")->check(Seconds());
  explore->add_option("--planner", o->planner, "start: planner of each leg");
  explore->add_flag("--wait", o->wait, "start: follow the exploration to its end; exit 0 only when complete");
  explore->add_flag("--measure", o->measure,
                    "with --wait: judge against navsim (collisions, distance) and the world (share mapped)");
  explore->add_option("--world", o->world, "with --measure: navsim's world file (default: the embedded one)");
  explore->add_option("--domain", o->domain, "with --measure: navsim's DDS domain id")->check(CLI::Range(0, 232));
  explore->add_option("--namespace", o->robot_namespace, "with --measure: robot namespace");
  explore->add_flag("--json", o->json, "Print one JSON object");
  return {explore, [&g, o] {
            o->dds_security = g.dds_security;
            navd::Client client(g.client);
            return navd::navctl::RunExplore(client, *o);
          }};
}

// `navctl truth`: navsim's ground truth, over DDS.
Command AddTruth(CLI::App& app, const Globals& g) {
  struct Args {
    int domain = 0;
    std::string ns, goal;
    double wait = 5.0;
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  auto* truth = app.add_subcommand("truth", "Print the simulator's ground truth (DDS)");
  truth->add_option("--domain", a->domain, "DDS domain id")->check(CLI::Range(0, 232));
  truth->add_option("--namespace", a->ns, "Robot namespace");
  truth->add_option("--wait", a->wait, "Seconds to wait for a sample")->check(Seconds());
  truth->add_flag("--json", a->json, "Print one JSON object");
  truth->add_option("--to", a->goal, "Also print the true distance to this X,Y");
  return {truth, [&g, a] {
            navd::TelemetryOptions topts;
            topts.dds.domain = a->domain;
            topts.dds.name = "navctl";
            topts.dds.security_enclave = g.dds_security;
            topts.robot_namespace = a->ns;
            navd::Telemetry telemetry(topts);
            const auto s = telemetry.WaitForSimStatus(a->wait);
            if (!s)
              throw std::runtime_error("no simulator status on DDS domain " + std::to_string(a->domain) + " within " +
                                       std::to_string(a->wait) + " s");
            std::optional<double> error;
            if (!a->goal.empty()) {
              const auto goal = ParseTuple(a->goal, "--to", 2, 3);
              error = std::hypot(s->x() - goal[0], s->y() - goal[1]);
            }
            if (a->json) {
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
          }};
}

Command AddDoor(CLI::App& app, const Globals& g) {
  auto o = std::make_shared<navd::navctl::DoorOptions>();
  auto action = std::make_shared<std::string>();
  auto* door = app.add_subcommand("door", "Open or close a simulator door by name (DDS)");
  door->add_option("name", o->name, "The door's name in the scenario")->required();
  door->add_option("action", *action, "open or close")->required()->check(CLI::IsMember({"open", "close"}));
  door->add_option("--domain", o->domain, "DDS domain id of navsim")->check(CLI::Range(0, 232));
  door->add_option("--wait", o->wait, "Seconds to wait for navsim to do it")->check(Seconds());
  door->add_flag("--json", o->json, "Print one JSON object");
  return {door, [&g, o, action] {
            o->close = *action == "close";
            o->dds_security = g.dds_security;
            return navd::navctl::RunDoor(*o);
          }};
}

Command AddReplay(CLI::App& app, const Globals& g) {
  auto o = std::make_shared<navd::navctl::ReplayOptions>();
  auto kidnap = std::make_shared<std::string>(), slip = std::make_shared<std::string>();
  auto* replay =
      app.add_subcommand("replay", "Play a CARMEN log over DDS like a robot while navd localises; judge its poses");
  replay->add_option("--log", o->log, "CARMEN log (.log or .log.gz)")->required();
  replay->add_option("--rate", o->rate, "Log seconds per wall second")->check(CLI::Range(0.01, 10000.0));
  replay->add_option("--domain", o->domain, "navd's DDS domain id")->check(CLI::Range(0, 232));
  replay->add_option("--namespace", o->robot_namespace, "Robot namespace of navd's topics");
  replay->add_option("--server", o->server, "navd's gRPC address, to set the first pose (\"\" to skip)");
  replay
      ->add_option("--odometry", o->odometry,
                   "noisy (the log's corrected poses corrupted by --odom-noise, seeded: the evaluation protocol, "
                   "default) or log (the odometry the log holds: ODOM lines, else FLASER's odometry fields)")
      ->check(CLI::IsMember({"noisy", "log"}));
  replay->add_option("--pairing", o->pairing,
                     "with --odometry log: how each scan takes the ODOM lines next to it: auto (as consecutive scans "
                     "matched against each other agree, default), stamp, or a share of the way from the line before "
                     "the scan (0) to the line after it (1), by stamp across a gap of over 1 s or where scans share "
                     "their two lines");
  replay->add_option("--odom-noise", o->odom_noise,
                     "T,R: relative translation noise, rad of heading noise per metre; T,R,S,D also errs the same "
                     "way every step: translation scaled by 1 + S, heading drifting D rad per metre");
  replay->add_option("--seed", o->seed, "Seed of the odometry noise");
  replay->add_option("--max-scans", o->max_scans, "Replay only the first N scans")->check(CLI::NonNegativeNumber);
  replay->add_option("--range-max", o->range_max, "Beams are cut at this range, metres")->check(CLI::Range(0.1, 100.0));
  replay
      ->add_option("--far-range-max", o->far_range_max,
                   "... or at this range in a scan with too few echoes within --range-max (an open hall), metres")
      ->check(CLI::Range(0.1, 100.0));
  replay->add_option("--out", o->out, "Write navd's poses as TUM (t x y z qx qy qz qw)");
  replay->add_flag("--strict", o->strict, "Stop at the first malformed log line");
  replay->add_option("--wait", o->wait, "Seconds to wait for navd on DDS")->check(Seconds());
  replay->add_option("--kidnap", *kidnap,
                     "T,DX,DY: at T s of log time the robot is carried DX,DY metres (its frame): the scans skip to "
                     "where the log has it nearest that point, its odometry stands still; reports when navd declared "
                     "itself lost and when it was back within 0.1 m");
  replay->add_option("--slip", *slip,
                     "T,DX,DY: at T s of log time the odometry slips DX,DY metres (its frame) over 1 s while the scans "
                     "go on; reports as --kidnap does");
  return {replay, [&g, o, kidnap, slip, replay] {
            if (replay->get_option("--pairing")->count() > 0 && o->odometry != "log")
              throw std::invalid_argument("--pairing is for --odometry log (the ODOM lines it pairs with the scans)");
            if (!kidnap->empty())
              navd::navctl::ParseDisturbance("--kidnap", *kidnap, navd::navctl::Disturbance::kKidnap, o.get());
            if (!slip->empty())
              navd::navctl::ParseDisturbance("--slip", *slip, navd::navctl::Disturbance::kSlip, o.get());
            o->dds_security = g.dds_security;
            return navd::navctl::RunReplay(*o);
          }};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"navctl: command-line client of navd"};
  app.require_subcommand(1);
  Globals g;
  app.add_option("--server", g.client.server, "navd address HOST:PORT");
  app.add_option("--tls-ca", g.client.tls_ca, "Connect over TLS, trusting navd's certificate if this PEM CA signed it");
  app.add_option("--tls-cert", g.client.tls_cert, "Mutual TLS: this client's PEM certificate (with --tls-key)");
  app.add_option("--tls-key", g.client.tls_key, "Mutual TLS: the PEM private key of --tls-cert");
  app.add_option("--tls-server-name", g.client.tls_server_name,
                 "The name navd's certificate carries, when --server's host is another (an IP address, say)");
  app.add_option("--token", g.client.token, "Bearer token for navd's roles (needs TLS)")->envname("NAVD_TOKEN");
  app.add_option("--dds-security", g.dds_security,
                 "DDS Security enclave (scripts/make-keystore's dds/enclaves/navctl) for the commands that use DDS: "
                 "truth, door, replay, follow/explore --measure");
  app.add_option("--deadline", g.client.timeout, "Deadline of each call, seconds")->check(Seconds());

  using navd::Client;
  const std::vector<Command> commands = {
      AddHealth(app, g),
      AddPlan(app, g),
      AddQuery(app, g, "planners", "List planners",
               [](Client& c, bool json_out) { navd::navctl::PrintPlanners(c.ListPlanners(), json_out); }),
      AddNavigate(app, g),
      AddFollow(app, g),
      AddDeliver(app, g),
      AddAction(app, g, "pause", "Pause the active mission (the robot stops, the mission stays)",
                [](Client& c) {
                  c.Pause();
                  std::printf("paused\n");
                }),
      AddAction(app, g, "resume", "Resume the paused mission",
                [](Client& c) {
                  c.Resume();
                  std::printf("resumed\n");
                }),
      AddQuery(app, g, "pose", "Print the pose estimate",
               [](Client& c, bool json_out) { navd::navctl::PrintPose(c.GetPose(), json_out); }),
      AddSetPose(app, g),
      AddAction(app, g, "relocalize", "Forget the pose and search the whole map for it",
                [](Client& c) {
                  c.GlobalRelocalize();
                  std::printf("relocalising: the estimate settles as the robot moves\n");
                }),
      AddLocalizers(app, g),
      AddAction(
          app, g, "cancel", "Cancel the active navigation",
          [](Client& c) { std::printf("%s\n", c.Cancel() ? "cancelled the active goal" : "no goal was active"); }),
      AddQuery(app, g, "status", "Print navigation status",
               [](Client& c, bool json_out) { navd::navctl::PrintStatus(c.GetStatus(), json_out); }),
      AddSpeedZones(app, g),
      AddQuery(app, g, "map", "Print the map's metadata",
               [](Client& c, bool json_out) { navd::navctl::PrintMapInfo(c.GetMap(true).info(), json_out); }),
      AddLoadMap(app, g),
      AddSaveMap(app, g),
      AddMapping(app, g),
      AddExplore(app, g),
      AddTruth(app, g),
      AddDoor(app, g),
      AddReplay(app, g),
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    for (const Command& command : commands)
      if (command.sub->parsed()) return command.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navctl: %s\n", e.what());
    return 1;
  }
  return 1;
}
