#include "client_lib/follow_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "client_lib/navctl_text.h"
#include "client_lib/pose_error_meter.h"
#include "client_lib/telemetry.h"
#include "dds/conversions.h"
#include "simulator/scenario.h"

namespace navd::navctl {

namespace {
double StampOf(const v1::Stamp& s) { return s.sec() + s.nanosec() * 1e-9; }
constexpr double kRadToDeg = 180.0 / M_PI;
}  // namespace

namespace {

// The mission of --waypoints or of --scenario's targets, with the options that shape it.
v1::FollowWaypointsRequest FollowRequest(const FollowOptions& o) {
  if (o.waypoints.empty() == o.scenario.empty()) {
    throw std::invalid_argument("follow needs --waypoints or --scenario (one of them)");
  }
  v1::FollowWaypointsRequest req;
  if (!o.scenario.empty()) {
    const sim::Scenario scenario = sim::LoadScenarioFile(o.scenario);
    if (scenario.targets.empty()) throw std::invalid_argument("--scenario " + o.scenario + " has no targets");
    for (const Point2& t : scenario.targets) {
      v1::Pose2D* w = req.add_waypoints();
      w->set_x(t.x());
      w->set_y(t.y());
    }
  } else {
    bool heading = false;
    for (const auto& t : ParseTupleList(o.waypoints, "--waypoints", &heading)) {
      v1::Pose2D* w = req.add_waypoints();
      w->set_x(t[0]);
      w->set_y(t[1]);
      w->set_theta(t[2]);
    }
    req.set_use_goal_heading(heading);
  }
  req.set_cyclic(o.cyclic);
  req.set_laps(o.laps);
  req.set_max_distance(o.max_distance);
  req.set_planner(o.planner);
  req.set_preempt(o.preempt);
  return req;
}

// --measure: the mission judged by navsim's ground truth over its own span of simulated time
// (from `start_stamp`, its first feedback, when there was one), into j["truth"] and, without
// --json, as text.
void ReportTruth(const FollowOptions& o, MeasuredRun& measured, PoseErrorMeter& meter, PeopleProximityMeter& proximity,
                 double start_stamp, const v1::NavigationResult& result, nlohmann::json& j) {
  const auto after = measured.telemetry->WaitForSimStatus(5.0);
  if (!after) throw std::runtime_error("--measure: the simulator stopped reporting");
  const double end_stamp = dds::FromTime(after->header().stamp());
  const double from = start_stamp >= 0.0 ? start_stamp : end_stamp - result.elapsed();
  meter.SetWindow(from, from + result.elapsed());
  const PoseErrorFigures e = meter.Figures();
  // Seed 000 reports its runs by their first 100 m of true travel.
  const double first_100m = meter.TimeToTravel(100.0, from);
  const double distance = after->distance_travelled() - measured.before.distance_travelled();
  const unsigned collisions = after->collisions() - measured.before.collisions();
  j["truth"] = {{"distance_travelled", distance},
                {"sim_time", result.elapsed()},
                {"collisions", collisions},
                {"mean_position_error", e.mean_position},
                {"rms_position_error", e.rms_position},
                {"max_position_error", e.max_position},
                {"mean_heading_error", e.mean_heading},
                {"samples", e.samples},
                {"mission_start", from}};
  if (first_100m >= 0.0) j["truth"]["time_to_first_100m"] = first_100m;
  proximity.SetWindow(from, from + result.elapsed());
  const ProximityFigures people = proximity.Figures();
  if (people.samples > 0) {
    j["truth"]["people"] = {{"time", people.time},
                            {"outside_personal_zone", people.outside_personal},
                            {"outside_intimate_zone", people.outside_intimate},
                            {"nearest", people.nearest}};
  }
  if (o.json) return;
  std::printf(
      "ground truth: %.2f m in %.1f s of simulated time; mean position error %.4f m (rms %.4f, max %.4f, %zu "
      "samples), mean heading error %.2f deg; collisions %u\n",
      distance, result.elapsed(), e.mean_position, e.rms_position, e.max_position, e.samples,
      e.mean_heading * kRadToDeg, collisions);
  if (first_100m >= 0.0) std::printf("ground truth: the first 100 m took %.1f s\n", first_100m);
  if (people.samples > 0) {
    std::printf(
        "ground truth: the nearest person was outside the personal zone (1.2 m) %.2f%% of %.1f s, outside "
        "the intimate zone (0.45 m) %.2f%%; closest approach %.2f m\n",
        100.0 * people.outside_personal, people.time, 100.0 * people.outside_intimate, people.nearest);
  }
}

}  // namespace

int RunFollow(Client& client, const FollowOptions& o) {
  const v1::FollowWaypointsRequest req = FollowRequest(o);
  // Ground truth and navd's estimates, matched by stamp, from before the mission starts.
  PoseErrorMeter meter;
  PeopleProximityMeter proximity(o.robot_namespace.empty() ? "robot" : o.robot_namespace);
  MeasuredRun measured;
  if (o.measure)
    measured = StartMeasuring(meter, {o.domain, dds::Network::kLoopback, "navctl-follow", {}, o.dds_security, {}},
                              o.robot_namespace, &proximity);

  double start_stamp = -1.0, last_print = -1e9;
  uint32_t recoveries = 0, reflexes = 0;  // the mission's counts, from its feedback
  const v1::NavigationResult result = client.FollowWaypoints(
      req,
      [&](const v1::NavigationFeedback& f) {
        const double t = StampOf(f.stamp());
        if (start_stamp < 0.0) start_stamp = t;
        recoveries = std::max(recoveries, f.recoveries());
        reflexes = std::max(reflexes, f.reflexes());
        if (o.json || t - last_print < 10.0) return;
        last_print = t;
        std::printf("  t=%7.1fs  %-9s %-14s waypoint %u/%u  lap %u  travelled %7.2f m  eta %5.0f s\n", t - start_stamp,
                    f.behaviour().c_str(), StateText(f.state()), f.mission_index() + 1, f.mission_count(),
                    f.laps_completed(), f.distance_travelled(), f.eta());
        std::fflush(stdout);
      },
      o.timeout);

  nlohmann::json j{{"outcome", OutcomeText(result.outcome())},
                   {"message", result.message()},
                   {"final_pose", PoseJson(result.final_pose())},
                   {"elapsed", result.elapsed()},
                   {"distance_travelled", result.distance_travelled()},
                   {"waypoints", req.waypoints_size()},
                   {"waypoints_reached", result.waypoints_reached()},
                   {"recoveries", recoveries},
                   {"sonar_reflexes", reflexes}};
  if (!o.json) {
    std::printf(
        "%s: %s; %u waypoints reached, %.2f m travelled (estimated) in %.1f s; %u recoveries, %u sonar reflexes\n",
        OutcomeText(result.outcome()), result.message().c_str(), result.waypoints_reached(),
        result.distance_travelled(), result.elapsed(), recoveries, reflexes);
  }
  if (measured.telemetry) ReportTruth(o, measured, meter, proximity, start_stamp, result, j);
  if (o.json) std::printf("%s\n", j.dump().c_str());
  return result.outcome() == v1::SUCCEEDED ? 0 : 1;
}

}  // namespace navd::navctl
