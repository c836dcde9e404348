#pragma once
// Pedestrians as in book chapter 7: each walks towards a goal with Gaussian-sampled speed plus
// Brownian motion; goals change every few seconds; newcomers arrive as a Poisson process. In a
// street (the chapter's setting) people walk along x towards a goal `goal_ahead` metres ahead, enter
// at one end and leave at the other; in a room they wander between random free goals. Each person
// is a disc the sensors see. Metres, seconds, map frame.
#include <functional>
#include <random>
#include <vector>

#include "services/common/world.h"
#include "services/common/ray_caster.h"
#include "services/common/disc.h"

namespace navd::sim {

struct CrowdDescription {
  Box area;              // where people walk, map frame
  bool street = true;    // street (walk along x, enter/leave at the ends) or room
  int initial_min = 10;  // people at the start: uniform in [initial_min, initial_max]
  int initial_max = 20;
  int max_people = 40;
  double arrival_rate = 0.5;     // 1/s, Poisson arrivals
  double speed_mean = 1.3;       // m/s
  double speed_std = 0.2;        // m/s
  double radius = 0.25;          // m
  double goal_ahead = 10.0;      // m (street)
  double goal_period_min = 2.0;  // s, goals change after a uniform draw in [min, max]
  double goal_period_max = 5.0;
  double brownian = 0.1;         // m/sqrt(s), std-dev of the random walk added to the motion
  double spawn_clearance = 1.0;  // m kept from robots when someone appears
};

struct Person {
  int id = 0;  // body id (Simulation numbers people from kFirstPersonId)
  Point2 position = Point2::Zero();
  Point2 velocity = Point2::Zero();  // m/s, measured over the last step
  Point2 goal = Point2::Zero();
  double speed = 0.0;  // m/s, preferred
  int direction = 1;   // street: +1 walks towards +x, -1 towards -x
  double next_goal_change = 0.0;
  double last_goal_change = 0.0;  // s: when they last took a new goal
  double last_step_aside = -1e9;  // s: when another person in their way last made them step aside
};

// Where a person walks: towards their goal at their preferred speed (m/s). Their step's velocity
// holds the Brownian motion as well, ~1 m/s of noise over a 0.01 s step.
Point2 WalkingVelocity(const Person& p);

// What occupies a disc: kFree, kWall, or the id of a body (robot, obstacle, other person) other
// than `self`. With `robots_only`, only robots count.
constexpr int kFree = -1;
constexpr int kWall = -2;
using OccupancyQuery = std::function<int(const Point2& centre, double radius, int self, bool robots_only)>;
// Reported when a person's step was stopped by a body (other than a person).
using ContactReport = std::function<void(const Person& person, int body)>;

class Crowd {
 public:
  static constexpr int kFirstPersonId = 100000;

  Crowd(const CrowdDescription& description, uint64_t seed);
  // Places the initial people at free spots.
  void Populate(double now, const OccupancyQuery& occupied);
  // Advances everyone by dt; people blocked by a wall or body stay put this step.
  void Step(double now, double dt, const OccupancyQuery& occupied, const ContactReport& contact);

  const std::vector<Person>& people() const { return people_; }
  const CrowdDescription& description() const { return d_; }
  int arrivals() const { return arrivals_; }
  int departures() const { return departures_; }
  int goal_changes() const { return goal_changes_; }

 private:
  bool Spawn(double now, bool at_street_end, const OccupancyQuery& occupied);
  void NewGoal(Person& p, double now);
  Point2 RandomPointInArea(double margin);

  CrowdDescription d_;
  std::mt19937_64 rng_;
  std::vector<Person> people_;
  double next_arrival_ = 0.0;
  int next_id_ = kFirstPersonId;
  int arrivals_ = 0, departures_ = 0, goal_changes_ = 0;
};

}  // namespace navd::sim
