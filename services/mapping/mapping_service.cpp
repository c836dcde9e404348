#include "services/mapping/mapping_service.h"

#include "services/common/common_service.h"
#include "services/common/world.h"

namespace navd::mapping {
namespace {
void FillInfo(const MapSnapshot& m, v1::MapInfo* info) {
  info->set_resolution(m.grid.resolution());
  info->set_width(m.grid.width());
  info->set_height(m.grid.height());
  ToProto(Pose2{m.grid.origin().x(), m.grid.origin().y(), 0.0}, info->mutable_origin());
  info->set_name(m.name);
  info->set_version(m.version);
}
}  // namespace

grpc::Status MappingService::GetMap(grpc::ServerContext*, const v1::GetMapRequest* request,
                                    v1::GetMapResponse* response) {
  return GuardedCall([&] {
    const auto map = maps_.Get();
    if (!map) throw Error(ErrorCode::kFailedPrecondition, "no map is loaded");
    FillInfo(*map, response->mutable_info());
    if (!request->info_only()) {
      const auto& cells = map->grid.cells();
      response->set_cells(reinterpret_cast<const char*>(cells.data()), cells.size());
    }
  });
}

grpc::Status MappingService::LoadMap(grpc::ServerContext*, const v1::LoadMapRequest* request,
                                     v1::LoadMapResponse* response) {
  return GuardedCall([&] {
    if (request->path().empty()) throw Error(ErrorCode::kInvalidArgument, "path is empty");
    std::string name;
    OccupancyGrid grid = LoadAnyMapFile(request->path(), &name);
    FillInfo(*maps_.Set(std::move(grid), name), response->mutable_info());
  });
}

}  // namespace navd::mapping
