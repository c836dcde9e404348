#pragma once
// The simulation's global DDS endpoints: rt/clock (simulated time), the world's truth
// (rt/sim/world_state: every robot, moving obstacle and person with its velocity, and the doors) and
// its collisions (rt/sim/collisions) out; door commands (rt/sim/door_command) in, which arrive on a DDS thread and wait
// until the simulation thread applies them between steps.
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "dds/participant.h"
#include "navsim_msgsPubSubTypes.h"
#include "rosgraph_msgsPubSubTypes.h"
#include "simulator/simulation.h"

namespace navd::sim {

class WorldTopics {
 public:
  explicit WorldTopics(dds::Participant& p);

  void PublishClock(double t);
  void PublishWorldState(double t, const Simulation& simulation);
  void PublishCollision(const CollisionEvent& e);
  // The door commands that arrived since the last call; a door the world lacks is warned about.
  void ApplyDoorCommands(Simulation& simulation);

 private:
  dds::Writer<rosgraph_msgs::msg::dds_::Clock_PubSubType> clock_;
  dds::Writer<navsim_msgs::msg::dds_::WorldState_PubSubType> world_;
  dds::Writer<navsim_msgs::msg::dds_::CollisionEvent_PubSubType> collisions_;
  std::mutex mutex_;
  std::vector<std::pair<std::string, bool>> pending_doors_;  // name, closed
  dds::Reader<navsim_msgs::msg::dds_::DoorCommand_PubSubType> door_commands_;
};

}  // namespace navd::sim
