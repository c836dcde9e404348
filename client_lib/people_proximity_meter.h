#pragma once
// How close a robot came to people, the figure of book chapter 7's street runs (Sec. 10.3): the
// distance from the robot's centre to the nearest person's centre, over time, judged by Hall's
// zones: the share of the time the nearest person was outside the personal zone (1.2 m) and
// outside the intimate zone (0.45 m). Fed with the simulator's bodies (rt/sim/world_state);
// samples are weighted by the time to the next one (a dropped sample does not skew the share).
// Thread-safe. Metres, seconds.
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "navsim_msgsPubSubTypes.h"

namespace navd {

struct ProximityFigures {
  double time = 0.0;              // s judged (with at least one person in the world)
  double outside_personal = 1.0;  // share of `time`
  double outside_intimate = 1.0;
  double nearest = std::numeric_limits<double>::infinity();  // m, the closest approach
  size_t samples = 0;
};

class PeopleProximityMeter {
 public:
  // robot_name: the robot's body in the world state ("robot" for an unnamed one).
  explicit PeopleProximityMeter(std::string robot_name) : robot_(std::move(robot_name)) {}
  void AddWorld(const navsim_msgs::msg::dds_::WorldState_& world);
  // The nearest person's distance at `stamp` (infinity: nobody around).
  void Add(double stamp, double nearest);
  // Only samples stamped in [from, to] count.
  void SetWindow(double from, double to);
  ProximityFigures Figures() const;

 private:
  mutable std::mutex mutex_;
  std::string robot_;
  std::vector<std::pair<double, double>> samples_;  // (stamp, nearest)
  double from_ = -1e300, to_ = 1e300;
};

}  // namespace navd
