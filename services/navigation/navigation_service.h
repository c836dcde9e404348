#pragma once
// gRPC adapter of navd.v1.NavigationService over the NavigationExecutive.
#include "navd/v1/navigation.grpc.pb.h"
#include "services/navigation/navigation_executive.h"

namespace navd::navigation {

class NavigationService final : public v1::NavigationService::Service {
 public:
  explicit NavigationService(NavigationExecutive& executive) : executive_(executive) {}
  grpc::Status NavigateTo(grpc::ServerContext* context, const v1::NavigateToRequest* request,
                          grpc::ServerWriter<v1::NavigateToResponse>* writer) override;
  grpc::Status FollowWaypoints(grpc::ServerContext* context, const v1::FollowWaypointsRequest* request,
                               grpc::ServerWriter<v1::NavigateToResponse>* writer) override;
  grpc::Status Deliver(grpc::ServerContext* context, const v1::DeliverRequest* request,
                       grpc::ServerWriter<v1::NavigateToResponse>* writer) override;
  grpc::Status PlanDeliveries(grpc::ServerContext* context, const v1::DeliverRequest* request,
                              v1::DeliverySchedule* response) override;
  grpc::Status Cancel(grpc::ServerContext* context, const v1::CancelRequest* request,
                      v1::CancelResponse* response) override;
  grpc::Status Pause(grpc::ServerContext* context, const v1::PauseRequest* request,
                     v1::PauseResponse* response) override;
  grpc::Status Resume(grpc::ServerContext* context, const v1::ResumeRequest* request,
                      v1::ResumeResponse* response) override;
  grpc::Status GetStatus(grpc::ServerContext* context, const v1::GetStatusRequest* request,
                         v1::GetStatusResponse* response) override;
  grpc::Status SetSpeedZones(grpc::ServerContext* context, const v1::SetSpeedZonesRequest* request,
                             v1::SpeedZones* response) override;
  grpc::Status GetSpeedZones(grpc::ServerContext* context, const v1::GetSpeedZonesRequest* request,
                             v1::SpeedZones* response) override;

 private:
  // Streams feedback of mission `goal_id` until it ends; cancels it when the caller goes away.
  grpc::Status StreamMission(grpc::ServerContext* context, grpc::ServerWriter<v1::NavigateToResponse>* writer,
                             uint64_t goal_id);

  NavigationExecutive& executive_;
};

}  // namespace navd::navigation
