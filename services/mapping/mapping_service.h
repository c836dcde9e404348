#pragma once
// gRPC adapter of navd.v1.MappingService: the served map (MapStore) and the mapping runs
// (MapBuilder), and exploration (navigation::Explorer, which builds a map as it drives).
#include <functional>
#include <optional>

#include "navd/v1/mapping.grpc.pb.h"
#include "services/common/map_store.h"
#include "services/mapping/map_builder.h"
#include "services/navigation/explorer.h"

namespace navd::mapping {

class MappingService final : public v1::MappingService::Service {
 public:
  // `robot_pose`: the localiser's current estimate (map frame), where a mapping run starts.
  // `exploring`: the options StartExploration starts from (the robot's clearance, ...).
  MappingService(MapStore& maps, MapBuilder& builder, navigation::Explorer& explorer,
                 navigation::ExplorerOptions exploring, std::function<std::optional<Pose2>()> robot_pose)
      : maps_(maps),
        builder_(builder),
        explorer_(explorer),
        exploring_(std::move(exploring)),
        robot_pose_(std::move(robot_pose)) {}
  grpc::Status GetMap(grpc::ServerContext* context, const v1::GetMapRequest* request,
                      grpc::ServerWriter<v1::GetMapResponse>* writer) override;
  grpc::Status LoadMap(grpc::ServerContext* context, const v1::LoadMapRequest* request,
                       v1::LoadMapResponse* response) override;
  grpc::Status SaveMap(grpc::ServerContext* context, const v1::SaveMapRequest* request,
                       v1::SaveMapResponse* response) override;
  grpc::Status StartMapping(grpc::ServerContext* context, const v1::StartMappingRequest* request,
                            v1::MappingStatus* response) override;
  grpc::Status StopMapping(grpc::ServerContext* context, const v1::StopMappingRequest* request,
                           v1::MappingStatus* response) override;
  grpc::Status GetMappingStatus(grpc::ServerContext* context, const v1::GetMappingStatusRequest* request,
                                v1::MappingStatus* response) override;
  grpc::Status StreamMapUpdates(grpc::ServerContext* context, const v1::StreamMapUpdatesRequest* request,
                                grpc::ServerWriter<v1::MapUpdate>* writer) override;
  grpc::Status StartExploration(grpc::ServerContext* context, const v1::StartExplorationRequest* request,
                                v1::ExplorationStatus* response) override;
  grpc::Status StopExploration(grpc::ServerContext* context, const v1::StopExplorationRequest* request,
                               v1::ExplorationStatus* response) override;
  grpc::Status GetExplorationStatus(grpc::ServerContext* context, const v1::GetExplorationStatusRequest* request,
                                    v1::ExplorationStatus* response) override;

 private:
  MapStore& maps_;
  MapBuilder& builder_;
  navigation::Explorer& explorer_;
  navigation::ExplorerOptions exploring_;
  std::function<std::optional<Pose2>()> robot_pose_;
};

}  // namespace navd::mapping
