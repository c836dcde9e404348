#include "services/planning/planning_service.h"

#include <thread>

#include "services/common/common_service.h"

namespace navd::planning {

namespace {
void ToProto(const PathPlan& plan, v1::ComputePathResponse* response) {
  for (const auto& p : plan.points) navd::ToProto(p, response->add_path());
  response->set_length(plan.length);
  response->set_planning_time(plan.planning_time);
  response->set_planner(plan.planner);
  response->set_expansions(plan.expansions);
  for (double v : plan.speed_limits) response->add_speed_limits(v);
  for (double v : plan.speeds) response->add_speeds(v);
  for (double t : plan.times) response->add_times(t);
  response->set_duration(plan.duration);
}
}  // namespace

grpc::ServerUnaryReactor* PlanningService::ComputePath(grpc::CallbackServerContext* context,
                                                       const v1::ComputePathRequest* request,
                                                       v1::ComputePathResponse* response) {
  grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
  if (engine_.PlansBriefly(request->planner())) {
    reactor->Finish(Plan(context, request, response));
  } else {
    // The call, its messages and this service outlive the thread: gRPC keeps them until Finish,
    // and server shutdown cancels the call (the plan polls for that) and waits for it.
    std::thread([this, context, request, response, reactor] {
      reactor->Finish(Plan(context, request, response));
    }).detach();
  }
  return reactor;
}

grpc::Status PlanningService::Plan(grpc::CallbackServerContext* context, const v1::ComputePathRequest* request,
                                   v1::ComputePathResponse* response) {
  return GuardedCall([&] {
    if (!request->has_start()) throw Error(ErrorCode::kInvalidArgument, "start is missing");
    if (!request->has_goal()) throw Error(ErrorCode::kInvalidArgument, "goal is missing");
    const std::map<std::string, double> options(request->options().begin(), request->options().end());
    PlanningScene scene;
    for (const auto& m : request->moving())
      scene.moving.push_back({FromProto(m.position()), FromProto(m.velocity()), m.radius(), m.person()});
    ToProto(engine_.ComputePath(FromProto(request->start()), FromProto(request->goal()), request->planner(), options,
                                StopWhenDone(context), scene),
            response);
  });
}

grpc::Status PlanningService::ComputePathThroughPoses(grpc::ServerContext* context,
                                                      const v1::ComputePathThroughPosesRequest* request,
                                                      v1::ComputePathResponse* response) {
  return GuardedCall([&] {
    if (!request->has_start()) throw Error(ErrorCode::kInvalidArgument, "start is missing");
    std::vector<Point2> waypoints;
    for (const auto& w : request->waypoints()) waypoints.push_back(FromProto(w));
    const std::map<std::string, double> options(request->options().begin(), request->options().end());
    ToProto(engine_.ComputePathThroughPoses(FromProto(request->start()), waypoints, request->planner(), options,
                                            StopWhenDone(context)),
            response);
  });
}

grpc::Status PlanningService::ListPlanners(grpc::ServerContext*, const v1::ListPlannersRequest*,
                                           v1::ListPlannersResponse* response) {
  return GuardedCall([&] {
    for (const auto& info : engine_.Planners()) {
      auto* p = response->add_planners();
      p->set_name(info.name);
      p->set_description(info.description);
      p->set_is_default(info.is_default);
      for (const auto& o : info.options) {
        auto* po = p->add_options();
        po->set_name(o.name);
        po->set_default_value(o.default_value);
        po->set_description(o.description);
      }
    }
  });
}

}  // namespace navd::planning
