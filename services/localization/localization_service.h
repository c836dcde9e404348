#pragma once
// gRPC adapter of navd.v1.LocalizationService over the LocalizerSelector.
#include "navd/v1/localization.grpc.pb.h"
#include "services/common/map_store.h"
#include "services/localization/localizer_selector.h"

namespace navd::localization {

class LocalizationService final : public v1::LocalizationService::Service {
 public:
  // `maps`: the served map, so SetPose can refuse poses off it or inside obstacles.
  LocalizationService(LocalizerSelector& localizer, const MapStore& maps) : localizer_(localizer), maps_(maps) {}
  grpc::Status GetPose(grpc::ServerContext* context, const v1::GetPoseRequest* request,
                       v1::GetPoseResponse* response) override;
  grpc::Status SetPose(grpc::ServerContext* context, const v1::SetPoseRequest* request,
                       v1::SetPoseResponse* response) override;
  grpc::Status GlobalRelocalize(grpc::ServerContext* context, const v1::GlobalRelocalizeRequest* request,
                                v1::GlobalRelocalizeResponse* response) override;
  grpc::Status ListMethods(grpc::ServerContext* context, const v1::ListMethodsRequest* request,
                           v1::ListMethodsResponse* response) override;
  grpc::Status SelectMethod(grpc::ServerContext* context, const v1::SelectMethodRequest* request,
                            v1::SelectMethodResponse* response) override;
  grpc::Status StreamPose(grpc::ServerContext* context, const v1::StreamPoseRequest* request,
                          grpc::ServerWriter<v1::GetPoseResponse>* writer) override;

 private:
  LocalizerSelector& localizer_;
  const MapStore& maps_;
};

}  // namespace navd::localization
