#pragma once
// gRPC adapter of navd.v1.MappingService over the MapStore.
#include "navd/v1/mapping.grpc.pb.h"
#include "services/common/map_store.h"

namespace navd::mapping {

class MappingService final : public v1::MappingService::Service {
 public:
  explicit MappingService(MapStore& maps) : maps_(maps) {}
  grpc::Status GetMap(grpc::ServerContext* context, const v1::GetMapRequest* request,
                      v1::GetMapResponse* response) override;
  grpc::Status LoadMap(grpc::ServerContext* context, const v1::LoadMapRequest* request,
                       v1::LoadMapResponse* response) override;

 private:
  MapStore& maps_;
};

}  // namespace navd::mapping
