#pragma once
// navctl door: opens or closes one of the simulator's doors by name over DDS
// (rt/sim/door_command) and waits until navsim's world state shows it done.
#include <string>

namespace navd::navctl {

struct DoorOptions {
  std::string name;
  bool close = false;
  int domain = 0;            // navsim's DDS domain
  std::string dds_security;  // DDS Security enclave (navctl --dds-security); empty: none
  double wait = 5.0;         // s for navsim to answer and to carry the command out
  bool json = false;
};

// Returns the process exit code: 0 when the door is in the requested state. Throws
// std::runtime_error with one readable line when navsim does not answer, has no such door or
// refuses (closing a door on a body).
int RunDoor(const DoorOptions& options);

}  // namespace navd::navctl
