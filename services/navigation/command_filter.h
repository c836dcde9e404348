#pragma once
// The executive's last word on a wheel command, after Nav2's collision monitor and speed filter:
// the motor behaviour the utility functions picked produces a command, and each filter in turn may
// slow or reshape it, one job per filter. The order is written in one place, where the executive
// builds its CommandFilterChain. Wheel speeds in m/s; points in the robot frame (x ahead), metres.
#include <functional>
#include <memory>
#include <vector>

#include "services/common/diff_drive.h"
#include "services/common/pose2.h"

namespace navd::navigation {

// Which motor behaviour produced the command (the guards watch over the ones that drive a path).
enum class CommandSource {
  kNavigation,   // the path follower (or the crowd controller, or the sonar reflex, on its leg)
  kGridReentry,  // driving back onto the navigation grid
  kOther,        // emergency stop, wake-up, avoidance manoeuvre, recovery
};

// What the filters know of the step. The point sets are gathered only when a filter asks.
struct CommandContext {
  CommandSource source = CommandSource::kOther;
  bool pose_valid = false;
  Pose2 pose;                       // the pose estimate, map frame
  bool among_people = false;        // people-aware navigation: the crowd controller does the avoiding
  bool tracking_obstacles = false;  // the moving-obstacle detection runs
  // The last scan's returns and the 3-D layer's cells nearby.
  std::function<std::vector<Point2>()> returns;
  // The rims of the tracked obstacles that move, now and where they will be within a second.
  std::function<std::vector<Point2>()> moving_rims;
  // m free behind the rim (the map, the rear sensor, obstacles tracked behind).
  std::function<double()> rear_room;
};

class CommandFilter {
 public:
  virtual ~CommandFilter() = default;
  virtual WheelSpeeds Filter(const WheelSpeeds& command, const CommandContext& context) = 0;
};

// The filters in the order they run.
class CommandFilterChain {
 public:
  void Add(std::shared_ptr<CommandFilter> filter) { filters_.push_back(std::move(filter)); }
  WheelSpeeds Apply(WheelSpeeds command, const CommandContext& context) const {
    for (const auto& f : filters_) command = f->Filter(command, context);
    return command;
  }

 private:
  std::vector<std::shared_ptr<CommandFilter>> filters_;
};

}  // namespace navd::navigation
