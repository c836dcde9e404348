#include "services/mapping/mapping_service.h"

#include <chrono>
#include <cstring>
#include <filesystem>
#include <thread>

#include "services/common/common_service.h"
#include "services/common/map_server_format.h"
#include "services/common/png_format.h"
#include "services/common/world.h"

namespace navd::mapping {
namespace {

void FillInfo(const OccupancyGrid& grid, const std::string& name, uint64_t version, v1::MapInfo* info) {
  info->set_resolution(grid.resolution());
  info->set_width(grid.width());
  info->set_height(grid.height());
  ToProto(Pose2{grid.origin().x(), grid.origin().y(), 0.0}, info->mutable_origin());
  info->set_name(name);
  info->set_version(version);
}

struct SourceMap {
  std::shared_ptr<const OccupancyGrid> grid;
  std::string name;
  uint64_t version = 0;
};

// The map a request names; FAILED_PRECONDITION when there is none.
SourceMap Resolve(v1::MapSource source, const MapStore& maps, const MapBuilder& builder) {
  if (source == v1::MAP_SOURCE_MAPPING) {
    const auto session = builder.session();
    if (!session) throw Error(ErrorCode::kFailedPrecondition, "source: no mapping run has started");
    const uint64_t version = session->status().version;  // read first: the map is at least this new
    return {session->Map(), "mapping", version};
  }
  const auto snapshot = maps.Get();
  if (!snapshot) throw Error(ErrorCode::kFailedPrecondition, "no map is loaded");
  // Share the snapshot's lifetime: the grid lives as long as the snapshot does.
  return {std::shared_ptr<const OccupancyGrid>(snapshot, &snapshot->grid), snapshot->name, snapshot->version};
}

void FillStatus(const MapBuilder& builder, v1::MappingStatus* out) {
  const auto session = builder.session();
  out->set_exists(session != nullptr);
  if (!session) return;
  const MappingStatus s = session->status();
  out->set_active(s.active);
  out->set_mode(s.mode == MappingMode::kSlam ? v1::MAPPING_MODE_SLAM : v1::MAPPING_MODE_KNOWN_POSES);
  out->set_scans(s.scans);
  out->set_dropped_scans(s.dropped);
  out->set_nodes(s.nodes);
  out->set_loop_closures(s.loop_closures);
  ToProto(s.pose, out->mutable_pose());
  out->set_version(s.version);
  FillInfo(*session->Map(), "mapping", s.version, out->mutable_info());
}

v1::ExplorationMethod MethodToProto(navigation::ExplorationMethod m) {
  switch (m) {
    case navigation::ExplorationMethod::kGreedy: return v1::EXPLORATION_METHOD_GREEDY;
    case navigation::ExplorationMethod::kVoronoiFastMarching: return v1::EXPLORATION_METHOD_VFM;
    case navigation::ExplorationMethod::kFrontier: break;
  }
  return v1::EXPLORATION_METHOD_FRONTIER;
}

void FillExploration(const navigation::ExplorationProgress& p, const MapBuilder& builder, v1::ExplorationStatus* out) {
  using navigation::ExplorationState;
  switch (p.state) {
    case ExplorationState::kIdle: out->set_state(v1::EXPLORATION_STATE_IDLE); break;
    case ExplorationState::kExploring: out->set_state(v1::EXPLORATION_STATE_EXPLORING); break;
    case ExplorationState::kComplete: out->set_state(v1::EXPLORATION_STATE_COMPLETE); break;
    case ExplorationState::kStopped: out->set_state(v1::EXPLORATION_STATE_STOPPED); break;
    case ExplorationState::kFailed: out->set_state(v1::EXPLORATION_STATE_FAILED); break;
  }
  out->set_method(MethodToProto(p.method));
  out->set_message(p.message);
  out->set_explored_area(p.explored_area);
  out->set_frontier_cells(p.frontier_cells);
  out->set_goals(p.goals);
  out->set_goals_given_up(p.goals_given_up);
  out->set_elapsed(p.elapsed);
  out->set_distance_travelled(p.distance_travelled);
  ToProto(p.goal, out->mutable_goal());
  FillStatus(builder, out->mutable_mapping());
}

}  // namespace

grpc::Status MappingService::GetMap(grpc::ServerContext* context, const v1::GetMapRequest* request,
                                    grpc::ServerWriter<v1::GetMapResponse>* writer) {
  return GuardedCall([&] {
    const SourceMap map = Resolve(request->source(), maps_, builder_);
    const OccupancyGrid& grid = *map.grid;
    v1::GetMapResponse chunk;
    FillInfo(grid, map.name, map.version, chunk.mutable_info());
    if (request->info_only()) {
      writer->Write(chunk);
      return;
    }
    const uint32_t width = static_cast<uint32_t>(grid.width()), height = static_cast<uint32_t>(grid.height());
    const uint32_t rows = request->chunk_rows() > 0 ? request->chunk_rows() : std::max<uint32_t>(1, (1u << 20) / width);
    const auto* cells = reinterpret_cast<const char*>(grid.cells().data());
    for (uint32_t first = 0; first < height && !context->IsCancelled(); first += rows) {
      const uint32_t n = std::min(rows, height - first);
      chunk.set_first_row(first);
      chunk.set_rows(n);
      chunk.set_cells(cells + static_cast<size_t>(first) * width, static_cast<size_t>(n) * width);
      if (!writer->Write(chunk)) return;  // the caller went away
    }
  });
}

grpc::Status MappingService::LoadMap(grpc::ServerContext*, const v1::LoadMapRequest* request,
                                     v1::LoadMapResponse* response) {
  return GuardedCall([&] {
    if (request->path().empty()) throw Error(ErrorCode::kInvalidArgument, "path is empty");
    std::string name;
    OccupancyGrid grid = LoadAnyMapFile(request->path(), &name);  // throws before the swap
    const auto snapshot = maps_.Set(std::move(grid), name);
    FillInfo(snapshot->grid, snapshot->name, snapshot->version, response->mutable_info());
  });
}

grpc::Status MappingService::SaveMap(grpc::ServerContext*, const v1::SaveMapRequest* request,
                                     v1::SaveMapResponse* response) {
  return GuardedCall([&] {
    if (request->path().empty()) throw Error(ErrorCode::kInvalidArgument, "path is empty");
    const SourceMap map = Resolve(request->source(), maps_, builder_);
    if (request->format() == v1::MAP_FORMAT_PNG) {
      SaveMapPng(*map.grid, request->path());
      response->add_files(request->path());
    } else {
      SaveMapServerMap(*map.grid, request->path());
      response->add_files(request->path());
      response->add_files(std::filesystem::path(request->path()).replace_extension(".pgm").string());
    }
    FillInfo(*map.grid, map.name, map.version, response->mutable_info());
  });
}

grpc::Status MappingService::StartMapping(grpc::ServerContext*, const v1::StartMappingRequest* request,
                                          v1::MappingStatus* response) {
  return GuardedCall([&] {
    MappingSessionOptions o;
    o.mode = request->mode() == v1::MAPPING_MODE_KNOWN_POSES ? MappingMode::kKnownPoses : MappingMode::kSlam;
    if (request->resolution() != 0.0) o.resolution = request->resolution();
    if (request->size() != 0.0) o.size = request->size();
    const std::optional<Pose2> start = robot_pose_();
    if (!start)
      throw Error(ErrorCode::kFailedPrecondition, "the robot has no pose estimate yet: mapping starts from it");
    builder_.Start(o, *start);
    FillStatus(builder_, response);
  });
}

grpc::Status MappingService::StopMapping(grpc::ServerContext*, const v1::StopMappingRequest* request,
                                         v1::MappingStatus* response) {
  return GuardedCall([&] {
    builder_.Stop();
    if (request->serve()) maps_.Set(*builder_.session()->Map(), "mapped");
    FillStatus(builder_, response);
  });
}

grpc::Status MappingService::GetMappingStatus(grpc::ServerContext*, const v1::GetMappingStatusRequest*,
                                              v1::MappingStatus* response) {
  return GuardedCall([&] { FillStatus(builder_, response); });
}

grpc::Status MappingService::StreamMapUpdates(grpc::ServerContext* context, const v1::StreamMapUpdatesRequest* request,
                                              grpc::ServerWriter<v1::MapUpdate>* writer) {
  return GuardedCall([&] {
    const double period = request->min_period() > 0.0 ? request->min_period() : 1.0;
    if (!(period <= 60.0)) throw Error(ErrorCode::kInvalidArgument, "min_period must be at most 60 seconds");
    const auto session = builder_.session();
    if (!session || !session->status().active) throw Error(ErrorCode::kFailedPrecondition, "no mapping run is active");
    uint64_t sent = 0;
    while (!context->IsCancelled()) {
      const bool active = session->status().active;
      uint64_t version = sent;
      if (const auto region = session->ChangedSince(sent, &version)) {
        const auto grid = session->Map();  // at least as new as `version`
        v1::MapUpdate update;
        FillInfo(*grid, "mapping", version, update.mutable_info());
        const int w = region->max.x - region->min.x + 1, h = region->max.y - region->min.y + 1;
        update.set_x(region->min.x);
        update.set_y(region->min.y);
        update.set_width(w);
        update.set_height(h);
        update.set_version(version);
        std::string cells(static_cast<size_t>(w) * h, '\0');
        for (int y = 0; y < h; ++y)
          std::memcpy(&cells[static_cast<size_t>(y) * w],
                      &grid->cells()[grid->Flat({region->min.x, region->min.y + y})], w);
        update.set_cells(std::move(cells));
        if (!writer->Write(update)) return;
        sent = version;
      }
      if (!active) return;  // the run ended and its last changes went out
      std::this_thread::sleep_for(std::chrono::duration<double>(period));
    }
  });
}

grpc::Status MappingService::StartExploration(grpc::ServerContext*, const v1::StartExplorationRequest* request,
                                              v1::ExplorationStatus* response) {
  return GuardedCall([&] {
    navigation::ExplorerOptions o = exploring_;
    switch (request->method()) {
      case v1::EXPLORATION_METHOD_FRONTIER: o.method = navigation::ExplorationMethod::kFrontier; break;
      case v1::EXPLORATION_METHOD_GREEDY: o.method = navigation::ExplorationMethod::kGreedy; break;
      case v1::EXPLORATION_METHOD_VFM: o.method = navigation::ExplorationMethod::kVoronoiFastMarching; break;
      default:
        throw Error(ErrorCode::kInvalidArgument,
                    "method: unknown exploration method " + std::to_string(request->method()));
    }
    if (request->resolution() != 0.0) o.mapping.resolution = request->resolution();
    if (request->size() != 0.0) o.mapping.size = request->size();
    o.max_time = request->max_time();
    o.planner = request->planner();
    FillExploration(explorer_.Start(o), builder_, response);
  });
}

grpc::Status MappingService::StopExploration(grpc::ServerContext*, const v1::StopExplorationRequest*,
                                             v1::ExplorationStatus* response) {
  return GuardedCall([&] { FillExploration(explorer_.Stop(), builder_, response); });
}

grpc::Status MappingService::GetExplorationStatus(grpc::ServerContext*, const v1::GetExplorationStatusRequest*,
                                                  v1::ExplorationStatus* response) {
  return GuardedCall([&] { FillExploration(explorer_.Progress(), builder_, response); });
}

}  // namespace navd::mapping
