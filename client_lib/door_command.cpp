#include "client_lib/door_command.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "dds/participant.h"
#include "dds/topics.h"
#include "navsim_msgsPubSubTypes.h"

namespace navd::navctl {
namespace {

using WorldState = navsim_msgs::msg::dds_::WorldState_PubSubType;
using DoorCommand = navsim_msgs::msg::dds_::DoorCommand_PubSubType;

// The door's state in the world state: -1 unknown door, 0 open, 1 closed.
int DoorState(const navsim_msgs::msg::dds_::WorldState_& w, const std::string& name) {
  for (const auto& d : w.doors()) {
    if (d.name() == name) return d.closed() ? 1 : 0;
  }
  return -1;
}

}  // namespace

int RunDoor(const DoorOptions& o) {
  dds::ParticipantOptions popts;
  popts.domain = o.domain;
  popts.name = "navctl";
  popts.security_enclave = o.dds_security;
  dds::Participant participant(popts);
  dds::Reader<WorldState> world(participant, dds::kWorldState, dds::Reliability::kBestEffort);
  dds::Writer<DoorCommand> writer(participant, dds::kDoorCommand, dds::Reliability::kReliable);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.wait);
  while (!world.Latest() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const auto first = world.Latest();
  if (!first) {
    throw std::runtime_error("no simulator world state on DDS domain " + std::to_string(o.domain) + " within " +
                             std::to_string(o.wait).substr(0, 4) + " s");
  }
  if (DoorState(*first, o.name) < 0) {
    std::string known;
    for (const auto& d : first->doors()) known += (known.empty() ? "" : ", ") + d.name();
    throw std::runtime_error("the simulator has no door '" + o.name + "' (doors: " + (known.empty() ? "none" : known) +
                             ")");
  }
  navsim_msgs::msg::dds_::DoorCommand_ command;
  command.name(o.name);
  command.closed(o.close);
  const int wanted = o.close ? 1 : 0;
  // Sent again until the world state shows it: the writer may not have met navsim's reader yet.
  auto next_send = std::chrono::steady_clock::now();
  while (true) {
    const auto w = world.Latest();
    if (w && DoorState(*w, o.name) == wanted) break;
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) {
      throw std::runtime_error("the simulator did not " + std::string(o.close ? "close" : "open") + " door '" + o.name +
                               "' within " + std::to_string(o.wait).substr(0, 4) +
                               " s (a door does not close on a robot or person; see navsim's log)");
    }
    if (now >= next_send) {
      writer.Write(command);
      next_send = now + std::chrono::milliseconds(250);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (o.json) {
    std::printf("%s\n", nlohmann::json{{"door", o.name}, {"closed", o.close}}.dump().c_str());
  } else {
    std::printf("door '%s' %s\n", o.name.c_str(), o.close ? "closed" : "open");
  }
  return 0;
}

}  // namespace navd::navctl
