#include "services/navigation/navigation_service.h"

#include <chrono>

#include "services/common/common_service.h"

namespace navd::navigation {
namespace {

// Feedback goes out at most this often; the result goes out at once.
constexpr double kFeedbackPeriod = 0.1;  // wall seconds

void ToProto(const NavigationFeedback& f, v1::NavigationFeedback* out) {
  out->set_state(static_cast<v1::NavigationState>(f.state));
  navd::ToProto(f.pose, out->mutable_pose());
  out->set_distance_remaining(f.distance_remaining);
  out->set_waypoint_index(f.waypoint_index);
  out->set_waypoint_count(f.waypoint_count);
  navd::ToProto(f.stamp, out->mutable_stamp());
  out->set_mission_index(f.mission_index);
  out->set_mission_count(f.mission_count);
  out->set_laps_completed(f.laps_completed);
  out->set_waypoints_reached(f.waypoints_reached);
  out->set_distance_travelled(f.distance_travelled);
  out->set_eta(f.eta);
  out->set_behaviour(f.behaviour);
  for (const ProcessUtility& u : f.utilities) {
    v1::ProcessUtility* p = out->add_utilities();
    p->set_name(u.name);
    p->set_motor(u.kind == ProcessKind::kMotor);
    p->set_utility(u.utility);
    p->set_gamma(u.gamma);
    p->set_active(u.active);
  }
  out->set_danger(f.danger);
  out->set_speed_limit(f.speed_limit);
  out->set_recoveries(f.recoveries);
  out->set_reflex(f.reflex);
  out->set_reflexes(f.reflexes);
  for (const planning::MovingBody& b : f.moving_obstacles) {
    v1::MovingBody* m = out->add_moving_obstacles();
    navd::ToProto(b.position, m->mutable_position());
    navd::ToProto(b.velocity, m->mutable_velocity());
    m->set_radius(b.radius);
    m->set_person(b.person);
  }
}

void ToProto(const SpeedZones& zones, v1::SpeedZones* out) {
  for (const SpeedZone& z : zones.zones()) {
    v1::SpeedZone* m = out->add_zones();
    m->set_name(z.name);
    for (const Point2& p : z.area) navd::ToProto(p, m->add_area());
    m->set_max_speed(z.max_speed);
  }
}

void ToProto(const NavigationStatus& s, v1::NavigationFeedback* out) {
  ToProto(s.feedback, out);
  out->set_hold_reason(s.hold_reason);
}

void ToProto(const NavigationResult& r, v1::NavigationResult* out) {
  out->set_outcome(static_cast<v1::Outcome>(r.outcome));
  out->set_message(r.message);
  navd::ToProto(r.final_pose, out->mutable_final_pose());
  out->set_distance_to_goal(r.distance_to_goal);
  out->set_elapsed(r.elapsed);
  out->set_path_length(r.path_length);
  out->set_distance_travelled(r.distance_travelled);
  out->set_waypoints_reached(r.waypoints_reached);
}

DeliveryRequest DeliveryFromProto(const v1::DeliverRequest& m) {
  DeliveryRequest r;
  for (int i = 0; i < m.tasks_size(); ++i) {
    const v1::DeliveryTask& t = m.tasks(i);
    const std::string field = "tasks[" + std::to_string(i) + "]";
    if (!t.has_pickup()) throw Error(ErrorCode::kInvalidArgument, field + ".pickup is missing");
    if (!t.has_dropoff()) throw Error(ErrorCode::kInvalidArgument, field + ".dropoff is missing");
    r.tasks.push_back({t.name().empty() ? "task " + std::to_string(i + 1) : t.name(), navd::FromProto(t.pickup()),
                       navd::FromProto(t.dropoff()), t.priority()});
  }
  r.options.capacity = m.capacity();
  r.options.return_to_start = m.return_to_start();
  r.planner = m.planner();
  r.preempt = m.preempt();
  return r;
}

void ToProto(const DeliverySchedule& s, const DeliveryRequest& r, double planning_time, v1::DeliverySchedule* out) {
  for (const DeliveryStop& stop : s.stops) {
    v1::DeliveryStop* m = out->add_stops();
    m->set_task(static_cast<uint32_t>(stop.task));
    m->set_name(r.tasks[stop.task].name);
    m->set_pickup(stop.pickup);
    navd::ToProto(stop.at, m->mutable_position());
    m->set_leg_length(stop.leg_length);
  }
  out->set_length(s.length);
  out->set_given_order_length(s.given_order_length);
  out->set_planning_time(planning_time);
}

double SecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

grpc::Status NavigationService::Deliver(grpc::ServerContext* context, const v1::DeliverRequest* request,
                                        grpc::ServerWriter<v1::NavigateToResponse>* writer) {
  uint64_t goal_id = 0;
  v1::NavigateToResponse first;
  grpc::Status started = GuardedCall([&] {
    const auto t0 = std::chrono::steady_clock::now();
    const DeliveryRequest r = DeliveryFromProto(*request);
    DeliverySchedule schedule;
    goal_id = executive_.Deliver(r, schedule, StopWhenDone(context));
    ToProto(schedule, r, SecondsSince(t0), first.mutable_schedule());
  });
  if (!started.ok()) return started;
  writer->Write(first);
  return StreamMission(context, writer, goal_id);
}

grpc::Status NavigationService::PlanDeliveries(grpc::ServerContext* context, const v1::DeliverRequest* request,
                                               v1::DeliverySchedule* response) {
  return GuardedCall([&] {
    const auto t0 = std::chrono::steady_clock::now();
    const DeliveryRequest r = DeliveryFromProto(*request);
    ToProto(executive_.PlanDeliveries(r, StopWhenDone(context)), r, SecondsSince(t0), response);
  });
}

grpc::Status NavigationService::NavigateTo(grpc::ServerContext* context, const v1::NavigateToRequest* request,
                                           grpc::ServerWriter<v1::NavigateToResponse>* writer) {
  uint64_t goal_id = 0;
  grpc::Status started = GuardedCall([&] {
    if (!request->has_goal()) throw Error(ErrorCode::kInvalidArgument, "goal is missing");
    goal_id = executive_.Navigate(
        {FromProto(request->goal()), request->use_goal_heading(), request->planner(), request->preempt()},
        StopWhenDone(context));
  });
  if (!started.ok()) return started;
  return StreamMission(context, writer, goal_id);
}

grpc::Status NavigationService::FollowWaypoints(grpc::ServerContext* context, const v1::FollowWaypointsRequest* request,
                                                grpc::ServerWriter<v1::NavigateToResponse>* writer) {
  uint64_t goal_id = 0;
  grpc::Status started = GuardedCall([&] {
    MissionRequest r;
    for (const auto& w : request->waypoints()) r.waypoints.push_back(FromProto(w));
    r.use_goal_heading = request->use_goal_heading();
    r.cyclic = request->cyclic();
    r.laps = request->laps();
    r.max_distance = request->max_distance();
    r.planner = request->planner();
    r.preempt = request->preempt();
    goal_id = executive_.FollowWaypoints(r, StopWhenDone(context));
  });
  if (!started.ok()) return started;
  return StreamMission(context, writer, goal_id);
}

grpc::Status NavigationService::StreamMission(grpc::ServerContext* context,
                                              grpc::ServerWriter<v1::NavigateToResponse>* writer, uint64_t goal_id) {
  const Navigator& nav = executive_.navigator();
  uint64_t seen = 0;
  auto last_feedback = std::chrono::steady_clock::time_point{};
  while (true) {
    seen = nav.WaitForChange(seen, kFeedbackPeriod);
    if (auto result = nav.ResultOf(goal_id)) {
      v1::NavigateToResponse msg;
      ToProto(*result, msg.mutable_result());
      writer->Write(msg);
      return grpc::Status::OK;
    }
    if (context->IsCancelled()) {
      // The caller went away or its deadline passed: a mission nobody watches is cancelled, so an
      // interrupted navctl stops the robot.
      executive_.Cancel(goal_id);
      return grpc::Status(grpc::StatusCode::CANCELLED, "navigation cancelled: the client cancelled the call");
    }
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_feedback).count() >= kFeedbackPeriod) {
      const NavigationStatus status = nav.Status();
      if (status.goal_id != goal_id) continue;
      v1::NavigateToResponse msg;
      ToProto(status, msg.mutable_feedback());
      if (!writer->Write(msg)) {
        executive_.Cancel(goal_id);
        return grpc::Status(grpc::StatusCode::CANCELLED, "navigation cancelled: the feedback stream broke");
      }
      last_feedback = now;
    }
  }
}

grpc::Status NavigationService::Cancel(grpc::ServerContext*, const v1::CancelRequest*, v1::CancelResponse* response) {
  return GuardedCall([&] { response->set_was_active(executive_.Cancel()); });
}

grpc::Status NavigationService::Pause(grpc::ServerContext*, const v1::PauseRequest*, v1::PauseResponse*) {
  return GuardedCall([&] { executive_.Pause(); });
}

grpc::Status NavigationService::Resume(grpc::ServerContext*, const v1::ResumeRequest*, v1::ResumeResponse*) {
  return GuardedCall([&] { executive_.Resume(); });
}

grpc::Status NavigationService::GetStatus(grpc::ServerContext*, const v1::GetStatusRequest*,
                                          v1::GetStatusResponse* response) {
  return GuardedCall([&] {
    const NavigationStatus s = executive_.navigator().Status();
    response->set_state(static_cast<v1::NavigationState>(s.feedback.state));
    response->set_active(s.active);
    response->set_sensors_stale(s.sensors_stale);
    navd::ToProto(s.goal.pose, response->mutable_goal());
    ToProto(s, response->mutable_feedback());
    response->set_paused(s.paused);
    response->set_localization_lost(executive_.localization_lost());
    response->set_localization_losses(executive_.localization_losses());
    if (s.last_result) ToProto(*s.last_result, response->mutable_last_result());
  });
}

grpc::Status NavigationService::SetSpeedZones(grpc::ServerContext*, const v1::SetSpeedZonesRequest* request,
                                              v1::SpeedZones* response) {
  return GuardedCall([&] {
    std::vector<SpeedZone> zones;
    for (const v1::SpeedZone& m : request->zones()) {
      SpeedZone z;
      z.name = m.name();
      for (const v1::Point2D& p : m.area()) z.area.push_back(FromProto(p));
      z.max_speed = m.max_speed();
      zones.push_back(std::move(z));
    }
    SpeedZones checked(std::move(zones));  // throws, naming the field, before anything changes
    ToProto(checked, response);
    executive_.SetSpeedZones(std::move(checked));
  });
}

grpc::Status NavigationService::GetSpeedZones(grpc::ServerContext*, const v1::GetSpeedZonesRequest*,
                                              v1::SpeedZones* response) {
  return GuardedCall([&] { ToProto(executive_.speed_zones(), response); });
}

}  // namespace navd::navigation
