// Book chapter 7's robustness test for the crowd RRT alone, in process: the pedestrian street
// scenario stepped by the simulator, the robot driven by the crowd controller (MPC around the
// crowd RRT) along the street's centre line for 88 m, N runs with new crowds. It separates the
// planner from the rest of navd (DDS, localisation), which scripts/street-runs measures whole:
//   --people truth  the chapter's own set-up: the planner knows every person's position and
//                   velocity within 45 m in front of the robot, and the robot's pose.
//   --people laser  navd's perception: the laser's unexplained blobs, tracked by the person
//                   tracker, from the true pose.
// and, to tell apart what the rest of the personal-zone time is made of:
//   --people truth-all            as truth, people behind the robot as well;
//   --people laser-true-velocity  the laser's tracks, each with its person's true walking velocity;
//   --straight-walkers            walkers who keep to one goal far down the street, without Brownian
//                                 motion, so constant-velocity predictions hold.
// Prints one line per run and the totals: collisions, close calls, the share of the time the nearest person
// was outside the personal zone (1.2 m, centre to centre), closest approach, and how many plans were
// escapes (nothing valid, or a short plan the escapes' fan replaced). With --collisions, each
// collision with the plans of the 2.5 s before it (and, for each, what it made of the person
// touched later: how far off and how fast it had them, and how close its way passed their
// prediction) and the tracker's view of who was touched (and when that person last took a new goal
// or stepped aside for someone). With laser people, also how good the tracking was near the robot
// (within 8 m): how far each detection and track was from the person's centre, how far off each
// track's velocity was from the velocity the person walks with, and the tracks' own velocity σ.
//   build/tests/street_bench [--runs N] [--first-seed S] [--people MODE] [--speed V] [--straight-walkers]
//   [--collisions]
//     [--approach-deceleration A] [--escape-time T] [--clearance-growth G] [--walking-clearance M] (the crowd RRT
//     options)
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "services/common/ray_caster.h"
#include "services/navigation/crowd_controller.h"
#include "services/navigation/moving_obstacle_detector.h"
#include "services/navigation/navigation_executive.h"
#include "services/navigation/person_tracker.h"
#include "services/planning/costmap.h"
#include "services/planning/personal_space.h"
#include "simulator/scenario.h"
#include "simulator/simulation.h"
#include "tests/support/simulated_drive.h"

namespace {

using namespace navd;

struct RunFigures {
  double time = 0.0;            // s, simulated
  double outside_personal = 0;  // s
  double turned = 0.0;          // rad, the robot's |yaw rate| integrated: how much it weaves
  double nearest = std::numeric_limits<double>::infinity();
  uint32_t collisions = 0;
  // Times the nearest person came within kCloseCall (a new one only after they were kCloseCallEnd
  // away): near misses, the situations collisions come from, three to four times as many.
  uint32_t close_calls = 0;
  uint32_t plans = 0, escapes = 0;  // escapes: nothing valid, or a short plan the escapes' fan replaced
  bool reached = false;
  // The tracker's errors (laser people only), for people within kTrackedRange of the robot: each
  // detection's distance from the person's centre, and each confirmed track's position and
  // velocity error (against the velocity the person walks with, towards their goal), every control period.
  std::vector<double> detection_errors, position_errors, velocity_errors;
  std::vector<double> velocity_stds;                          // the tracks' own velocity σ (the larger axis), m/s
  std::vector<double> coasting_errors, seen_velocity_errors;  // tracks unseen for a scan or more; the others' velocity
};
constexpr double kTrackedRange = 8.0;                      // m
constexpr double kCloseCall = 0.70, kCloseCallEnd = 0.90;  // m, centre to centre (contact: 0.55)

enum class Knowledge { kTruth, kTruthAll, kLaser, kLaserTrueVelocity };

using sim::WalkingVelocity;

// The person nearest `at` within `within` metres, or none.
const sim::Person* NearestPerson(const std::vector<sim::Person>& people, const Point2& at, double within) {
  const sim::Person* nearest = nullptr;
  for (const sim::Person& p : people) {
    if (Distance(p.position, at) < within) {
      within = Distance(p.position, at);
      nearest = &p;
    }
  }
  return nearest;
}

// The median, 90th and 99th percentiles of `values` (sorted here), or "none".
std::string Quantiles(std::vector<double>& values) {
  if (values.empty()) return "none";
  std::sort(values.begin(), values.end());
  char text[80];
  std::snprintf(text, sizeof text, "median %.3f, 90%% %.3f, 99%% %.3f", values[values.size() / 2],
                values[values.size() * 9 / 10], values[values.size() * 99 / 100]);
  return text;
}

// `planner`: navd's crowd RRT options with the command line's changes; speed and radius are set here.
RunFigures Run(const sim::Scenario& scenario, uint64_t seed, Knowledge knowledge, double distance, bool print_contacts,
               double speed, const planning::CrowdRrtOptions& planner,
               const navigation::PersonTrackerOptions& tracking) {
  const bool truth_people = knowledge == Knowledge::kTruth || knowledge == Knowledge::kTruthAll;
  sim::SimulationOptions so;
  so.seed = seed;
  sim::Simulation s(scenario, so);
  const World& world = s.world();
  planning::CostmapOptions co;  // navd's defaults: --inflation-margin 0.1, --cost-decay 0.5
  co.inflation_radius = world.robot.radius + 0.10;
  co.decay_radius = 0.5;
  const planning::Costmap costmap(std::make_shared<OccupancyGrid>(world.map), co);

  navigation::PeopleAwareOptions people;  // navd's defaults
  people.tracking = tracking;
  navigation::CrowdControllerOptions control = people.control;
  control.planner = planner;
  control.limits = {std::min(speed, world.robot.max_speed), world.robot.max_angular_speed, world.robot.max_accel,
                    world.robot.max_angular_accel};
  control.planner.desired_speed = control.limits.max_speed;
  control.planner.robot_radius = world.robot.radius;
  navigation::CrowdController controller(control);
  navigation::MovingObstacleDetector segmenter(people.detection);
  segmenter.SetMap(std::make_shared<RayCaster>(world.map));
  navigation::PersonTracker tracker(people.tracking);

  const Pose2 start = s.robot().base().true_pose();
  const double goal_x = start.x + distance, y = start.y;
  const double control_period = 0.05, dt = s.options().physics_step;
  double next_control = 0.0;
  RunFigures f;
  bool close = false;   // within a close call
  double driven = 0.0;  // m/s before the step: a collision stalls the robot
  // The plans of the last 2.5 s, for --collisions: what each was, what it knew of the people, and
  // where each person truly was and walked then.
  struct RecentPlan {
    double time = 0.0;
    std::string line;
    planning::CrowdTrajectory plan;
    std::vector<planning::MovingBody> bodies;
    std::vector<sim::Person> people;
  };
  std::deque<RecentPlan> recent_plans;
  while (s.now() < 4.0 * distance / control.limits.max_speed) {
    const Pose2 pose = s.robot().base().true_pose();
    if (pose.x >= goal_x) {
      f.reached = true;
      break;
    }
    if (s.now() >= next_control - 1e-9) {
      next_control += control_period;
      std::vector<Point2> path;
      for (double x = std::max(pose.x, start.x); x <= std::min(goal_x + 5.0, pose.x + control.lookahead); x += 0.1)
        path.emplace_back(x, y);
      std::vector<planning::MovingBody> bodies;
      if (truth_people) {
        for (const sim::Person& p : s.people()) {
          const Point2 rel = pose.inverse() * p.position;
          if ((rel.x() > 0.0 || knowledge == Knowledge::kTruthAll) && rel.norm() <= 45.0)
            bodies.push_back({p.position, WalkingVelocity(p), people.person_radius, true});
        }
      } else {
        for (const navigation::TrackedPerson& t : tracker.People(s.now())) {
          Point2 velocity = t.velocity;
          if (knowledge == Knowledge::kLaserTrueVelocity) {
            // The person the track is on: the nearest within half a metre.
            if (const sim::Person* on = NearestPerson(s.people(), t.position, 0.5)) velocity = WalkingVelocity(*on);
          }
          bodies.push_back({t.position, velocity, people.person_radius, true});
          if (Distance(t.position, pose.translation()) > kTrackedRange) continue;
          const sim::Person* truth = NearestPerson(s.people(), t.position, 0.5);
          if (!truth) continue;
          f.position_errors.push_back(Distance(t.position, truth->position));
          f.velocity_errors.push_back((t.velocity - WalkingVelocity(*truth)).norm());
          f.velocity_stds.push_back(navigation::VelocityStd(t));
          if (s.now() - t.last_seen > 0.15) {  // not in the last scan (10 Hz)
            f.coasting_errors.push_back(Distance(t.position, truth->position));
          } else {
            f.seen_velocity_errors.push_back((t.velocity - WalkingVelocity(*truth)).norm());
          }
        }
      }
      const uint64_t plans_before = controller.plans();
      const navigation::UnicycleCommand u = controller.Step(costmap, pose, path, bodies, s.now());
      const bool replanned = controller.plans() != plans_before;
      if (replanned) {
        ++f.plans;
        f.escapes += controller.plan().escape;
      }
      if (print_contacts && replanned) {
        const planning::CrowdTrajectory& plan = controller.plan();
        double nearest_gap = std::numeric_limits<double>::infinity();  // rim to rim, as tracked
        for (const planning::MovingBody& b : bodies)
          nearest_gap = std::min(nearest_gap, Distance(b.position, pose.translation()) - b.radius - world.robot.radius);
        char line[300];
        std::snprintf(line, sizeof line,
                      "    plan at %.2f s, robot at %.2f m/s: %s for %.2f s, first input (%.2f m/s², %.2f rad/s²), "
                      "ends at %.2f m/s; nearest rim %.2f m",
                      s.now(), s.robot().base().true_twist().vx,
                      plan.escape    ? "escape"
                      : plan.braking ? "braking"
                                     : "driving",
                      plan.states.back().t, plan.inputs.empty() ? 0.0 : plan.inputs[0].accel,
                      plan.inputs.empty() ? 0.0 : plan.inputs[0].yaw_accel, plan.states.back().v, nearest_gap);
        recent_plans.push_back({s.now(), line, plan, bodies, s.people()});
        while (recent_plans.front().time < s.now() - 2.5) recent_plans.pop_front();
      }
      s.Command(0, {u.v, 0.0, u.w});
      driven = s.robot().base().true_twist().vx;
    }
    const sim::StepOutputs out = s.Step();
    if (print_contacts) {
      // Each collision: how fast the robot went, the plan it drove, and who was next to it.
      const Pose2 rp = s.robot().base().true_pose();
      for (const sim::CollisionEvent& e : out.events) {
        // Whom it touched: a person's id, or none (a wall, anything else).
        const int touched = e.other_id >= sim::Crowd::kFirstPersonId ? e.other_id : -1;
        for (const RecentPlan& r : recent_plans) {
          std::printf("%s\n", r.line.c_str());
          // What the plan made of the person it later touched: their nearest body, and the least gap
          // (rim to rim) between the plan's way and that body's prediction.
          const auto who =
              std::find_if(r.people.begin(), r.people.end(), [&](const sim::Person& p) { return p.id == touched; });
          if (who == r.people.end()) continue;
          const planning::MovingBody* body = nullptr;
          for (const planning::MovingBody& b : r.bodies)
            if (!body || Distance(b.position, who->position) < Distance(body->position, who->position)) body = &b;
          if (!body || Distance(body->position, who->position) > 1.0) {
            std::printf("      the person touched later: not among the plan's people (none within 1 m of them)\n");
            continue;
          }
          double least = std::numeric_limits<double>::infinity(), least_t = 0.0;
          for (const planning::UnicycleState& st : r.plan.states) {
            const double gap =
                Distance(st.position(), body->position + st.t * body->velocity) - body->radius - world.robot.radius;
            if (gap < least) {
              least = gap;
              least_t = st.t;
            }
          }
          const Point2 v = WalkingVelocity(*who);
          std::printf(
              "      the person touched later: %.2f m off, velocity (%.2f, %.2f), true (%.2f, %.2f); "
              "planned gap %.2f m at +%.2f s\n",
              Distance(body->position, who->position), body->velocity.x(), body->velocity.y(), v.x(), v.y(), least,
              least_t);
        }
        std::printf(
            "  collision at %.2f s with %s, robot at (%.2f, %.2f) driven at %.2f m/s, closing at %.2f m/s, the other "
            "at "
            "%.2f m/s; plan %s, cost %.1f\n",
            e.time, e.other.c_str(), rp.x, rp.y, driven, e.robot_closing, e.other_closing,
            controller.plan().escape    ? "escape"
            : controller.plan().braking ? "braking"
                                        : "driving",
            controller.plan().cost);
        for (const sim::Person& p : s.people()) {
          if (Distance(p.position, rp.translation()) > 0.6) continue;
          const Point2 rel = rp.inverse() * p.position;
          std::printf(
              "    person %d at (%.2f, %.2f) in the robot's frame; new goal %.2f s ago, stepped aside %.2f s ago\n",
              p.id, rel.x(), rel.y(), s.now() - p.last_goal_change, s.now() - p.last_step_aside);
          if (truth_people) continue;
          // What the tracker made of them: the nearest track, as the planner last saw it.
          const navigation::TrackedPerson* track = nullptr;
          for (const navigation::TrackedPerson& t : tracker.tracks())
            if (Distance(t.position, p.position) < 0.6 &&
                (!track || Distance(t.position, p.position) < Distance(track->position, p.position)))
              track = &t;
          if (!track) {
            std::printf("      no track within 0.6 m\n");
            continue;
          }
          const Point2 v = WalkingVelocity(p);
          std::printf(
              "      track %d%s, %d hits, seen %.2f-%.2f s, %.2f m off; velocity (%.2f, %.2f) sigma %.2f, true (%.2f, "
              "%.2f)\n",
              track->id, track->confirmed ? "" : " (unconfirmed)", track->hits, track->first_seen, track->last_seen,
              Distance(track->position, p.position), track->velocity.x(), track->velocity.y(),
              navigation::VelocityStd(*track), v.x(), v.y());
        }
      }
    }
    if (!truth_people && out.robots[0].scan) {
      const localization::ScanReading scan = localization::ToScan(s, *out.robots[0].scan);
      std::vector<Point2> seen;
      for (const navigation::DetectedObstacle& blob : segmenter.Segment(scan, s.robot().base().true_pose()))
        if (blob.radius <= people.max_person_radius) {
          seen.push_back(blob.position);
          if (Distance(blob.position, s.robot().base().true_pose().translation()) > kTrackedRange) continue;
          if (const sim::Person* truth = NearestPerson(s.people(), blob.position, 0.5))
            f.detection_errors.push_back(Distance(blob.position, truth->position));
        }
      tracker.Update(seen, s.now());
    }
    double nearest = std::numeric_limits<double>::infinity();
    for (const sim::Person& p : s.people())
      nearest = std::min(nearest, Distance(p.position, s.robot().base().true_pose().translation()));
    f.time += dt;
    f.turned += std::abs(s.robot().base().true_twist().omega) * dt;
    if (nearest > planning::kPersonalZone) f.outside_personal += dt;
    if (nearest < kCloseCall && !close) ++f.close_calls;
    close = nearest < kCloseCall || (close && nearest < kCloseCallEnd);
    f.nearest = std::min(f.nearest, nearest);
  }
  f.collisions = s.robot().collisions();
  return f;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"book chapter 7's street runs for the crowd RRT alone (in process)"};
  int runs = 50;
  uint64_t first = 1;
  std::string people = "truth";
  std::string scenario_path = "worlds/scenarios/street.yaml";
  double distance = 88.0;
  app.add_option("--runs", runs)->check(CLI::Range(1, 10000));
  app.add_option("--first-seed", first);
  app.add_option("--people", people,
                 "truth (the chapter's: known within 45 m ahead), truth-all (and behind), laser (navd's tracker) or "
                 "laser-true-velocity (its tracks with the true walking velocities)")
      ->check(CLI::IsMember({"truth", "truth-all", "laser", "laser-true-velocity"}));
  app.add_option("--scenario", scenario_path);
  app.add_option("--distance", distance, "metres down the street")->check(CLI::Range(1.0, 1000.0));
  double speed = 1.5;
  app.add_option("--speed", speed, "desired speed among people, m/s (navd --crowd-speed)")->check(CLI::Range(0.1, 5.0));
  planning::CrowdRrtOptions planner = navigation::PeopleAwareOptions{}.control.planner;
  app.add_option(
         "--approach-deceleration", planner.approach_deceleration,
         "m/s²: plans too fast to stop short of someone ahead are pruned unless braking (0: off, navd's default)")
      ->check(CLI::Range(0.0, 10.0));
  app.add_option("--escape-time", planner.escape_time, "s: how long each escape manoeuvre is judged for")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 5.0));
  app.add_option("--clearance-growth", planner.clearance_growth,
                 "the clearance from a walker grows by this share of the distance they are predicted to walk")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 2.0));
  app.add_option("--walking-clearance", planner.walking_clearance, "m kept from walkers beyond the clearance")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  navigation::PersonTrackerOptions tracking = navigation::PeopleAwareOptions{}.tracking;
  app.add_option("--track-measurement-std", tracking.measurement_std, "m: the person tracker's detection noise")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 1.0));
  app.add_option("--track-acceleration-std", tracking.acceleration_std,
                 "m/s²: the person tracker's walker acceleration noise")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 20.0));
  bool straight = false;
  app.add_flag("--straight-walkers", straight, "walkers keep one goal far down the street, no Brownian motion");
  bool print_contacts = false;
  app.add_flag(
      "--collisions", print_contacts,
      "print each collision (with a person or a wall): the robot's speed, the plans of the 2.5 s before, who was near");
  CLI11_PARSE(app, argc, argv);

  sim::Scenario scenario;
  try {
    scenario = sim::LoadScenarioFile(scenario_path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "street_bench: %s\n", e.what());
    return 1;
  }
  if (!scenario.crowd) {
    std::fprintf(stderr, "street_bench: %s has no people\n", scenario_path.c_str());
    return 1;
  }
  if (straight) {
    scenario.crowd->goal_ahead = 1000.0;
    scenario.crowd->goal_period_min = scenario.crowd->goal_period_max = 1000.0;
    scenario.crowd->brownian = 0.0;
  }
  const Knowledge knowledge = people == "truth"       ? Knowledge::kTruth
                              : people == "truth-all" ? Knowledge::kTruthAll
                              : people == "laser"     ? Knowledge::kLaser
                                                      : Knowledge::kLaserTrueVelocity;
  const auto t0 = std::chrono::steady_clock::now();
  double time = 0.0, outside = 0.0, turned = 0.0, nearest = std::numeric_limits<double>::infinity();
  uint32_t collisions = 0, close_calls = 0, plans = 0, escapes = 0;
  int reached = 0, clean = 0;
  std::vector<double> shares, detection_errors, position_errors, velocity_errors, coasting_errors, seen_velocity_errors,
      velocity_stds;
  for (int i = 0; i < runs; ++i) {
    const uint64_t seed = first + static_cast<uint64_t>(i);
    const RunFigures f = Run(scenario, seed, knowledge, distance, print_contacts, speed, planner, tracking);
    std::printf(
        "seed %lu: %s, %.1f s, collisions %u, close calls %u, outside personal %.3f, nearest %.2f m, escapes %u of %u "
        "plans\n",
        static_cast<unsigned long>(seed), f.reached ? "reached" : "timed out", f.time, f.collisions, f.close_calls,
        f.outside_personal / f.time, f.nearest, f.escapes, f.plans);
    std::fflush(stdout);
    time += f.time;
    outside += f.outside_personal;
    turned += f.turned;
    collisions += f.collisions;
    close_calls += f.close_calls;
    plans += f.plans;
    escapes += f.escapes;
    nearest = std::min(nearest, f.nearest);
    reached += f.reached;
    clean += f.collisions == 0;
    shares.push_back(f.outside_personal / f.time);
    detection_errors.insert(detection_errors.end(), f.detection_errors.begin(), f.detection_errors.end());
    position_errors.insert(position_errors.end(), f.position_errors.begin(), f.position_errors.end());
    velocity_errors.insert(velocity_errors.end(), f.velocity_errors.begin(), f.velocity_errors.end());
    velocity_stds.insert(velocity_stds.end(), f.velocity_stds.begin(), f.velocity_stds.end());
    coasting_errors.insert(coasting_errors.end(), f.coasting_errors.begin(), f.coasting_errors.end());
    seen_velocity_errors.insert(seen_velocity_errors.end(), f.seen_velocity_errors.begin(),
                                f.seen_velocity_errors.end());
  }
  std::sort(shares.begin(), shares.end());
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "street bench (%s people): %d/%d reached, %u collisions (%d runs without), %u close calls (within %.2f m), "
      "%.1f s simulated; outside the personal zone %.2f%% of the time (per run: min %.1f%%, median %.1f%%); closest "
      "%.2f m; mean |yaw rate| %.2f rad/s; escapes %u of %u plans; %.0f s wall\n",
      people.c_str(), reached, runs, collisions, clean, close_calls, kCloseCall, time, 100.0 * outside / time,
      100.0 * shares.front(), 100.0 * shares[shares.size() / 2], nearest, turned / time, escapes, plans, wall);
  if (!position_errors.empty()) {
    std::printf("tracking within %.0f m: detections off by %s m; tracks off by %s m, their velocity by %s m/s\n",
                kTrackedRange, Quantiles(detection_errors).c_str(), Quantiles(position_errors).c_str(),
                Quantiles(velocity_errors).c_str());
    std::printf("  tracks seen in the last scan: velocity off by %s m/s; unseen (%zu of %zu): off by %s m\n",
                Quantiles(seen_velocity_errors).c_str(), coasting_errors.size(), position_errors.size(),
                Quantiles(coasting_errors).c_str());
    std::printf("  the tracks' own velocity sigma: %s m/s\n", Quantiles(velocity_stds).c_str());
  }
  return 0;
}
