// The gRPC request validation of every navd service: a fuzzed request message goes into navd's own
// adapters over a real in-process gRPC server, built over the default world as the daemon builds
// it (no DDS, no control loop). The first byte picks the method, the rest is the request message;
// bytes that are no valid message of that type are left to protobuf, which gRPC runs before navd
// sees a call. Any answer is fine (OK or a status naming the field); a crash, a leak, undefined
// behaviour or a call that outlives its deadline by seconds is a bug the fuzzer reports.
//
// LoadMap and SaveMap are left out: they take a file path from the request and read or write it,
// which a fuzzer must not do to the machine it runs on (map_server_fuzzer fuzzes the map parsers).
#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>
#include <grpcpp/grpcpp.h>
#include <grpcpp/impl/client_unary_call.h>
#include <grpcpp/support/sync_stream.h>

#include <chrono>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "services/common/clock.h"
#include "services/common/map_store.h"
#include "services/common/world.h"
#include "services/localization/localization_service.h"
#include "services/localization/localizer_selector.h"
#include "services/localization/odometry_localizer.h"
#include "services/localization/particle_filter.h"
#include "services/mapping/mapping_service.h"
#include "services/mapping/slam_localizer.h"
#include "services/navigation/explorer.h"
#include "services/navigation/navigation_executive.h"
#include "services/navigation/navigation_service.h"
#include "services/planning/planner_catalog.h"
#include "services/planning/planning_engine.h"
#include "services/planning/planning_service.h"

namespace {

// A call that starts a mission or a stream runs until its deadline: short, so the fuzzer moves on.
constexpr auto kDeadline = std::chrono::milliseconds(50);

// navd's services as the daemon wires them, served in-process.
struct Navd {
  navd::MapStore maps;
  std::unique_ptr<navd::planning::PlanningEngine> planning;
  navd::mapping::MapBuilder map_builder;
  navd::localization::LocalizerSelector localizer{/*search_on_its_own_thread=*/true};
  navd::SystemClock clock;
  std::unique_ptr<navd::navigation::NavigationExecutive> executive;
  std::unique_ptr<navd::navigation::Explorer> explorer;
  std::unique_ptr<navd::planning::PlanningService> planning_service;
  std::unique_ptr<navd::localization::LocalizationService> localization_service;
  std::unique_ptr<navd::mapping::MappingService> mapping_service;
  std::unique_ptr<navd::navigation::NavigationService> navigation_service;
  std::unique_ptr<grpc::Server> server;
  std::shared_ptr<grpc::Channel> channel;
  std::vector<const google::protobuf::MethodDescriptor*> methods;

  Navd() {
    using namespace navd;
    World world = DefaultWorld();
    const Pose2 start = world.start;
    maps.Set(std::move(world.map), world.name);
    planning = std::make_unique<planning::PlanningEngine>(maps, planning::PlanningEngineOptions{});
    planning::RegisterDefaultPlanners(*planning);
    const auto map = maps.Get();
    localizer.Add(std::make_unique<localization::ParticleFilterLocalizer>(map->grid));
    localizer.Add(std::make_unique<localization::OdometryLocalizer>());
    localizer.Add(std::make_unique<mapping::SlamLocalizer>(map_builder));
    localizer.SetPose(start, Eigen::Matrix3d::Zero());
    executive =
        std::make_unique<navigation::NavigationExecutive>(*planning, localizer, clock, navigation::NavigatorOptions{});
    explorer = std::make_unique<navigation::Explorer>(maps, map_builder, *executive, *planning, localizer, clock);
    planning_service = std::make_unique<planning::PlanningService>(*planning);
    localization_service = std::make_unique<localization::LocalizationService>(localizer, maps);
    mapping_service = std::make_unique<mapping::MappingService>(
        maps, map_builder, *explorer, navigation::ExplorerOptions{}, [this]() -> std::optional<Pose2> {
          const localization::PoseEstimate e = localizer.Estimate();
          if (!e.valid) return std::nullopt;
          return e.pose;
        });
    navigation_service = std::make_unique<navigation::NavigationService>(*executive);

    grpc::ServerBuilder builder;
    builder.RegisterService(planning_service.get());
    builder.RegisterService(localization_service.get());
    builder.RegisterService(mapping_service.get());
    builder.RegisterService(navigation_service.get());
    server = builder.BuildAndStart();
    channel = server->InProcessChannel(grpc::ChannelArguments());

    const auto* pool = google::protobuf::DescriptorPool::generated_pool();
    for (const char* name : {"navd.v1.PlanningService", "navd.v1.LocalizationService", "navd.v1.MappingService",
                             "navd.v1.NavigationService"}) {
      const google::protobuf::ServiceDescriptor* service = pool->FindServiceByName(name);
      for (int i = 0; i < service->method_count(); ++i) {
        const std::string& method = service->method(i)->name();
        if (method != "LoadMap" && method != "SaveMap") methods.push_back(service->method(i));
      }
    }
  }

  // One call of `method` with `request` as the generated stubs make it (their blocking unary call
  // and server-streaming reader, over the serialized message; gRPC's generic stub offers only the
  // asynchronous API here): every response read, then the status.
  void Call(const google::protobuf::MethodDescriptor* method, const std::string& request) const {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + kDeadline);
    const std::string path = "/" + method->service()->full_name() + "/" + method->name();
    grpc::Slice slice(request);
    const grpc::ByteBuffer message(&slice, 1);
    grpc::ByteBuffer response;
    if (!method->server_streaming()) {
      grpc::internal::BlockingUnaryCall<grpc::ByteBuffer, grpc::ByteBuffer>(
          channel.get(), grpc::internal::RpcMethod(path.c_str(), grpc::internal::RpcMethod::NORMAL_RPC), &context,
          message, &response);
      return;
    }
    std::unique_ptr<grpc::ClientReader<grpc::ByteBuffer>> reader(
        grpc::internal::ClientReaderFactory<grpc::ByteBuffer>::Create(
            channel.get(), grpc::internal::RpcMethod(path.c_str(), grpc::internal::RpcMethod::SERVER_STREAMING),
            &context, message));
    while (reader->Read(&response)) {
    }
    reader->Finish();
  }
};

// navd lives as long as the process, as its server threads do. At exit its server is shut down
// before LeakSanitizer looks (its check runs after every handler registered later than it): calls
// still in the server's worker threads would otherwise read as leaks.
Navd* TheNavd() {
  static Navd* navd = [] {
    auto* created = new Navd();
    std::atexit([] {
      grpc::Server& server = *TheNavd()->server;
      server.Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(1));
      server.Wait();
    });
    return created;
  }();
  return navd;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Navd* navd = TheNavd();
  if (size == 0) return -1;
  const google::protobuf::MethodDescriptor* method = navd->methods[data[0] % navd->methods.size()];
  std::unique_ptr<google::protobuf::Message> request(
      google::protobuf::MessageFactory::generated_factory()->GetPrototype(method->input_type())->New());
  if (!request->ParseFromArray(data + 1, static_cast<int>(size - 1))) return -1;
  navd->Call(method, request->SerializeAsString());
  return 0;
}
