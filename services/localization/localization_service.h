#pragma once
// gRPC adapter of navd.v1.LocalizationService over a Localizer.
#include "navd/v1/localization.grpc.pb.h"
#include "services/localization/localizer.h"

namespace navd::localization {

class LocalizationService final : public v1::LocalizationService::Service {
 public:
  explicit LocalizationService(Localizer& localizer) : localizer_(localizer) {}
  grpc::Status GetPose(grpc::ServerContext* context, const v1::GetPoseRequest* request,
                       v1::GetPoseResponse* response) override;
  grpc::Status SetPose(grpc::ServerContext* context, const v1::SetPoseRequest* request,
                       v1::SetPoseResponse* response) override;

 private:
  Localizer& localizer_;
};

}  // namespace navd::localization
