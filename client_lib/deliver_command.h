#pragma once
// navctl deliver: a delivery mission. navd orders the tasks' pickups and dropoffs (capacity,
// priorities) into a round and drives it; navctl prints the schedule, progress by stop, the result.
#include <cstdint>
#include <string>
#include <vector>

#include "client_lib/navd_client.h"

namespace navd::navctl {

struct DeliverOptions {
  std::vector<std::string> tasks;  // "NAME:PX,PY:DX,DY[:PRIORITY]"
  uint32_t capacity = 0;           // 0: no limit
  bool return_to_start = false;
  bool plan_only = false;  // print the schedule; the robot does not move
  std::string planner;
  bool preempt = false;
  double timeout = 0.0;  // s of wall time, 0 = none
  bool json = false;
};

// Parses one --task; throws std::invalid_argument naming it.
v1::DeliveryTask ParseDeliveryTask(const std::string& text);
// Returns the process exit code: 0 when the mission succeeded (or, with plan_only, was scheduled).
int RunDeliver(Client& client, const DeliverOptions& options);

}  // namespace navd::navctl
