#include "services/planning/planning_service.h"

#include "services/common/common_service.h"

namespace navd::planning {

grpc::Status PlanningService::ComputePath(grpc::ServerContext* context, const v1::ComputePathRequest* request,
                                          v1::ComputePathResponse* response) {
  return GuardedCall([&] {
    if (!request->has_start()) throw Error(ErrorCode::kInvalidArgument, "start is missing");
    if (!request->has_goal()) throw Error(ErrorCode::kInvalidArgument, "goal is missing");
    const std::map<std::string, double> options(request->options().begin(), request->options().end());
    const PathPlan plan = engine_.ComputePath(FromProto(request->start()), FromProto(request->goal()),
                                              request->planner(), options, StopWhenDone(context));
    for (const auto& p : plan.points) ToProto(p, response->add_path());
    response->set_length(plan.length);
    response->set_planning_time(plan.planning_time);
    response->set_planner(plan.planner);
    response->set_expansions(plan.expansions);
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
