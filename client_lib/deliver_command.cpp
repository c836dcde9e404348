#include "client_lib/deliver_command.h"

#include <cstdio>
#include <stdexcept>

#include "client_lib/navctl_text.h"

namespace navd::navctl {

namespace {

std::string StopText(const v1::DeliveryStop& s) {
  return std::string(s.pickup() ? "pick up" : "drop off") + " '" + s.name() + "'";
}

nlohmann::json ScheduleJson(const v1::DeliverySchedule& schedule) {
  nlohmann::json stops = nlohmann::json::array();
  for (const v1::DeliveryStop& s : schedule.stops()) {
    stops.push_back({{"task", s.task()},
                     {"name", s.name()},
                     {"action", s.pickup() ? "pickup" : "dropoff"},
                     {"x", s.position().x()},
                     {"y", s.position().y()},
                     {"leg_length", s.leg_length()}});
  }
  return {{"stops", stops},
          {"length", schedule.length()},
          {"given_order_length", schedule.given_order_length()},
          {"planning_time", schedule.planning_time()}};
}

void PrintSchedule(const v1::DeliverySchedule& schedule) {
  std::printf("schedule: %d stops, %.2f m (each task in turn as given: %.2f m), planned in %.2f s\n",
              schedule.stops_size(), schedule.length(), schedule.given_order_length(), schedule.planning_time());
  for (int i = 0; i < schedule.stops_size(); ++i) {
    const v1::DeliveryStop& s = schedule.stops(i);
    std::printf("  %2d. %-24s at (%.2f, %.2f)  %6.2f m\n", i + 1, StopText(s).c_str(), s.position().x(),
                s.position().y(), s.leg_length());
  }
  std::fflush(stdout);
}

}  // namespace

v1::DeliveryTask ParseDeliveryTask(const std::string& text) {
  // NAME:PX,PY:DX,DY[:PRIORITY]
  std::vector<std::string> parts;
  size_t from = 0;
  while (true) {
    const size_t colon = text.find(':', from);
    parts.push_back(text.substr(from, colon == std::string::npos ? std::string::npos : colon - from));
    if (colon == std::string::npos) break;
    from = colon + 1;
  }
  if (parts.size() < 3 || parts.size() > 4 || parts[0].empty()) {
    throw std::invalid_argument("--task '" + text +
                                "': expected NAME:PICKUP_X,PICKUP_Y:DROPOFF_X,DROPOFF_Y[:PRIORITY]");
  }
  const auto pickup = ParseTuple(parts[1], "--task " + parts[0] + " pickup", 2, 2);
  const auto dropoff = ParseTuple(parts[2], "--task " + parts[0] + " dropoff", 2, 2);
  v1::DeliveryTask t;
  t.set_name(parts[0]);
  t.mutable_pickup()->set_x(pickup[0]);
  t.mutable_pickup()->set_y(pickup[1]);
  t.mutable_dropoff()->set_x(dropoff[0]);
  t.mutable_dropoff()->set_y(dropoff[1]);
  if (parts.size() == 4) {
    const auto priority = ParseTuple(parts[3], "--task " + parts[0] + " priority", 1, 1);
    if (priority[0] != static_cast<int>(priority[0])) {
      throw std::invalid_argument("--task " + parts[0] + " priority: must be a whole number");
    }
    t.set_priority(static_cast<int>(priority[0]));
  }
  return t;
}

int RunDeliver(Client& client, const DeliverOptions& o) {
  if (o.tasks.empty()) throw std::invalid_argument("deliver needs at least one --task");
  v1::DeliverRequest req;
  for (const std::string& t : o.tasks) *req.add_tasks() = ParseDeliveryTask(t);
  req.set_capacity(o.capacity);
  req.set_return_to_start(o.return_to_start);
  req.set_planner(o.planner);
  req.set_preempt(o.preempt);

  if (o.plan_only) {
    const v1::DeliverySchedule schedule = client.PlanDeliveries(req);
    if (o.json) {
      std::printf("%s\n", nlohmann::json{{"schedule", ScheduleJson(schedule)}}.dump().c_str());
    } else {
      PrintSchedule(schedule);
    }
    return 0;
  }

  v1::DeliverySchedule schedule;
  uint32_t last_index = UINT32_MAX;
  const v1::NavigationResult result = client.Deliver(
      req,
      [&](const v1::DeliverySchedule& s) {
        schedule = s;
        if (!o.json) PrintSchedule(s);
      },
      [&](const v1::NavigationFeedback& f) {
        if (o.json || f.mission_index() == last_index) return;
        last_index = f.mission_index();
        const int i = static_cast<int>(f.mission_index());
        const std::string what = i < schedule.stops_size() ? StopText(schedule.stops(i)) : "back to the start";
        std::printf("  stop %d/%u: %s (travelled %.2f m)\n", i + 1, f.mission_count(), what.c_str(),
                    f.distance_travelled());
        std::fflush(stdout);
      },
      o.timeout);
  if (o.json) {
    std::printf("%s\n", nlohmann::json{{"schedule", ScheduleJson(schedule)},
                                       {"outcome", OutcomeText(result.outcome())},
                                       {"message", result.message()},
                                       {"stops_reached", result.waypoints_reached()},
                                       {"distance_travelled", result.distance_travelled()},
                                       {"elapsed", result.elapsed()}}
                            .dump()
                            .c_str());
  } else {
    std::printf("%s: %s; %u stops reached, %.2f m travelled (estimated) in %.1f s\n", OutcomeText(result.outcome()),
                result.message().c_str(), result.waypoints_reached(), result.distance_travelled(), result.elapsed());
  }
  return result.outcome() == v1::SUCCEEDED ? 0 : 1;
}

}  // namespace navd::navctl
