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
  grpc::Status Cancel(grpc::ServerContext* context, const v1::CancelRequest* request,
                      v1::CancelResponse* response) override;
  grpc::Status GetStatus(grpc::ServerContext* context, const v1::GetStatusRequest* request,
                         v1::GetStatusResponse* response) override;

 private:
  NavigationExecutive& executive_;
};

}  // namespace navd::navigation
