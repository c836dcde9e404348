#pragma once
// gRPC adapter of navd.v1.PlanningService over PlanningEngine. ComputePath, the call clients make
// by the thousand, uses gRPC's callback API: a brief plan (grid and graph planners) runs on the
// thread that read the request, with no hand-over to a worker thread and back (the synchronous
// API's thread wake-ups cost as much CPU as a short plan, and the plan finds its scratch arrays
// warm in that thread's cache); a time-budgeted plan (OMPL, kinodynamic) gets a thread of its own,
// so it never holds up the callback threads that serve other requests.
#include "navd/v1/planning.grpc.pb.h"
#include "services/planning/planning_engine.h"

namespace navd::planning {

class PlanningService final : public v1::PlanningService::WithCallbackMethod_ComputePath<v1::PlanningService::Service> {
 public:
  explicit PlanningService(PlanningEngine& engine) : engine_(engine) {}
  grpc::ServerUnaryReactor* ComputePath(grpc::CallbackServerContext* context, const v1::ComputePathRequest* request,
                                        v1::ComputePathResponse* response) override;
  grpc::Status ComputePathThroughPoses(grpc::ServerContext* context, const v1::ComputePathThroughPosesRequest* request,
                                       v1::ComputePathResponse* response) override;
  grpc::Status ListPlanners(grpc::ServerContext* context, const v1::ListPlannersRequest* request,
                            v1::ListPlannersResponse* response) override;

 private:
  grpc::Status Plan(grpc::CallbackServerContext* context, const v1::ComputePathRequest* request,
                    v1::ComputePathResponse* response);

  PlanningEngine& engine_;
};

}  // namespace navd::planning
