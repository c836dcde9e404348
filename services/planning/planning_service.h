#pragma once
// gRPC adapter of navd.v1.PlanningService over PlanningEngine.
#include "navd/v1/planning.grpc.pb.h"
#include "services/planning/planning_engine.h"

namespace navd::planning {

class PlanningService final : public v1::PlanningService::Service {
 public:
  explicit PlanningService(PlanningEngine& engine) : engine_(engine) {}
  grpc::Status ComputePath(grpc::ServerContext* context, const v1::ComputePathRequest* request,
                           v1::ComputePathResponse* response) override;
  grpc::Status ComputePathThroughPoses(grpc::ServerContext* context, const v1::ComputePathThroughPosesRequest* request,
                                       v1::ComputePathResponse* response) override;
  grpc::Status ListPlanners(grpc::ServerContext* context, const v1::ListPlannersRequest* request,
                            v1::ListPlannersResponse* response) override;

 private:
  PlanningEngine& engine_;
};

}  // namespace navd::planning
