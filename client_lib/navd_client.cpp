#include "client_lib/navd_client.h"

#include <chrono>

#include "services/common/error.h"
#include "services/common/text_file.h"

namespace navd {
namespace {

std::string ReadPemFile(const std::string& path, const char* what) {
  try {
    return ReadTextFile(path, what);
  } catch (const Error& e) {
    throw ClientError(grpc::StatusCode::INVALID_ARGUMENT, e.what());
  }
}

std::shared_ptr<grpc::ChannelCredentials> ChannelCredentials(const ClientOptions& o) {
  const bool tls = !o.tls_ca.empty() || !o.tls_cert.empty();
  if (!tls) {
    if (!o.token.empty()) {
      throw ClientError(grpc::StatusCode::INVALID_ARGUMENT,
                        "a token is sent only over TLS: give the CA that signed navd's certificate (--tls-ca)");
    }
    return grpc::InsecureChannelCredentials();
  }
  if (o.tls_cert.empty() != o.tls_key.empty()) {
    throw ClientError(grpc::StatusCode::INVALID_ARGUMENT, "--tls-cert and --tls-key go together");
  }
  grpc::SslCredentialsOptions ssl;
  if (!o.tls_ca.empty()) ssl.pem_root_certs = ReadPemFile(o.tls_ca, "TLS CA file");
  if (!o.tls_cert.empty()) {
    ssl.pem_cert_chain = ReadPemFile(o.tls_cert, "TLS certificate file");
    ssl.pem_private_key = ReadPemFile(o.tls_key, "TLS key file");
  }
  std::shared_ptr<grpc::ChannelCredentials> credentials = grpc::SslCredentials(ssl);
  if (!o.token.empty()) {
    credentials = grpc::CompositeChannelCredentials(credentials, grpc::AccessTokenCredentials(o.token));
  }
  return credentials;
}

}  // namespace

Client::Client(const ClientOptions& options) : options_(options) {
  grpc::ChannelArguments arguments;
  if (!options.tls_server_name.empty()) arguments.SetSslTargetNameOverride(options.tls_server_name);
  channel_ = grpc::CreateCustomChannel(options.server, ChannelCredentials(options), arguments);
  health_ = grpc::health::v1::Health::NewStub(channel_);
  planning_ = v1::PlanningService::NewStub(channel_);
  localization_ = v1::LocalizationService::NewStub(channel_);
  mapping_ = v1::MappingService::NewStub(channel_);
  navigation_ = v1::NavigationService::NewStub(channel_);
}

void Client::Prepare(grpc::ClientContext& context, double timeout) const {
  if (timeout > 0) {
    context.set_deadline(
        std::chrono::system_clock::now() +
        std::chrono::duration_cast<std::chrono::system_clock::duration>(std::chrono::duration<double>(timeout)));
  }
}

void Client::Fail(const grpc::Status& status) const {
  std::string message = status.error_message();
  if (status.error_code() == grpc::StatusCode::UNAVAILABLE) {
    message = "cannot reach navd at " + options_.server + " (" + message + ")";
  } else if (status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED && message == "Deadline Exceeded") {
    message = "navd at " + options_.server + " did not answer before the deadline";
  }
  throw ClientError(status.error_code(), message);
}

bool Client::WaitForConnected(double timeout) {
  return channel_->WaitForConnected(std::chrono::system_clock::now() +
                                    std::chrono::milliseconds(static_cast<int64_t>(timeout * 1000)));
}

grpc::health::v1::HealthCheckResponse::ServingStatus Client::Health(const std::string& service) {
  grpc::health::v1::HealthCheckRequest req;
  req.set_service(service);
  return Call(*health_, &grpc::health::v1::Health::Stub::Check, req).status();
}

v1::ComputePathResponse Client::ComputePath(double start_x, double start_y, double goal_x, double goal_y,
                                            const std::string& planner, const std::map<std::string, double>& options,
                                            const std::vector<v1::MovingBody>& moving) {
  v1::ComputePathRequest req;
  for (const auto& m : moving) *req.add_moving() = m;
  req.mutable_start()->set_x(start_x);
  req.mutable_start()->set_y(start_y);
  req.mutable_goal()->set_x(goal_x);
  req.mutable_goal()->set_y(goal_y);
  req.set_planner(planner);
  for (const auto& [k, v] : options) (*req.mutable_options())[k] = v;
  return Call(*planning_, &v1::PlanningService::Stub::ComputePath, req);
}

v1::ComputePathResponse Client::ComputePathThroughPoses(double start_x, double start_y,
                                                        const std::vector<std::pair<double, double>>& waypoints,
                                                        const std::string& planner) {
  v1::ComputePathThroughPosesRequest req;
  req.mutable_start()->set_x(start_x);
  req.mutable_start()->set_y(start_y);
  for (const auto& [x, y] : waypoints) {
    auto* w = req.add_waypoints();
    w->set_x(x);
    w->set_y(y);
  }
  req.set_planner(planner);
  return Call(*planning_, &v1::PlanningService::Stub::ComputePathThroughPoses, req);
}

v1::ListPlannersResponse Client::ListPlanners() {
  return Call(*planning_, &v1::PlanningService::Stub::ListPlanners, v1::ListPlannersRequest());
}

v1::GetPoseResponse Client::GetPose() {
  return Call(*localization_, &v1::LocalizationService::Stub::GetPose, v1::GetPoseRequest());
}

void Client::SetPose(double x, double y, double theta) {
  v1::SetPoseRequest req;
  req.mutable_pose()->set_x(x);
  req.mutable_pose()->set_y(y);
  req.mutable_pose()->set_theta(theta);
  Call(*localization_, &v1::LocalizationService::Stub::SetPose, req);
}

void Client::GlobalRelocalize() {
  Call(*localization_, &v1::LocalizationService::Stub::GlobalRelocalize, v1::GlobalRelocalizeRequest());
}

v1::ListMethodsResponse Client::ListMethods() {
  return Call(*localization_, &v1::LocalizationService::Stub::ListMethods, v1::ListMethodsRequest());
}

void Client::SelectMethod(const std::string& method) {
  v1::SelectMethodRequest req;
  req.set_method(method);
  Call(*localization_, &v1::LocalizationService::Stub::SelectMethod, req);
}

void Client::StreamPose(double rate_hz, const std::function<bool(const v1::GetPoseResponse&)>& on_pose,
                        double timeout) {
  grpc::ClientContext ctx;
  Prepare(ctx, timeout);
  v1::StreamPoseRequest req;
  req.set_rate_hz(rate_hz);
  auto reader = localization_->StreamPose(&ctx, req);
  ReadWatch<v1::GetPoseResponse>(ctx, *reader, on_pose);
}

v1::GetMapResponse Client::GetMap(bool info_only, v1::MapSource source) {
  grpc::ClientContext ctx;
  Prepare(ctx, options_.timeout);
  v1::GetMapRequest req;
  req.set_info_only(info_only);
  req.set_source(source);
  auto reader = mapping_->GetMap(&ctx, req);
  // The chunks' rows joined into one message.
  v1::GetMapResponse whole, chunk;
  std::string cells;
  while (reader->Read(&chunk)) {
    *whole.mutable_info() = chunk.info();
    cells += chunk.cells();
  }
  const grpc::Status s = reader->Finish();
  if (!s.ok()) Fail(s);
  whole.set_rows(whole.info().height());
  if (!info_only) whole.set_cells(std::move(cells));
  return whole;
}

v1::SaveMapResponse Client::SaveMap(const std::string& path, v1::MapFormat format, v1::MapSource source) {
  v1::SaveMapRequest req;
  req.set_path(path);
  req.set_format(format);
  req.set_source(source);
  return Call(*mapping_, &v1::MappingService::Stub::SaveMap, req);
}

v1::MappingStatus Client::StartMapping(v1::MappingMode mode, double resolution, double size) {
  v1::StartMappingRequest req;
  req.set_mode(mode);
  req.set_resolution(resolution);
  req.set_size(size);
  return Call(*mapping_, &v1::MappingService::Stub::StartMapping, req);
}

v1::MappingStatus Client::StopMapping(bool serve) {
  v1::StopMappingRequest req;
  req.set_serve(serve);
  return Call(*mapping_, &v1::MappingService::Stub::StopMapping, req);
}

v1::MappingStatus Client::GetMappingStatus() {
  return Call(*mapping_, &v1::MappingService::Stub::GetMappingStatus, v1::GetMappingStatusRequest());
}

v1::ExplorationStatus Client::StartExploration(const v1::StartExplorationRequest& request) {
  return Call(*mapping_, &v1::MappingService::Stub::StartExploration, request);
}

v1::ExplorationStatus Client::StopExploration() {
  return Call(*mapping_, &v1::MappingService::Stub::StopExploration, v1::StopExplorationRequest());
}

v1::ExplorationStatus Client::GetExplorationStatus() {
  return Call(*mapping_, &v1::MappingService::Stub::GetExplorationStatus, v1::GetExplorationStatusRequest());
}

void Client::StreamMapUpdates(double min_period, const std::function<bool(const v1::MapUpdate&)>& on_update,
                              double timeout) {
  grpc::ClientContext ctx;
  Prepare(ctx, timeout);
  v1::StreamMapUpdatesRequest req;
  req.set_min_period(min_period);
  auto reader = mapping_->StreamMapUpdates(&ctx, req);
  ReadWatch<v1::MapUpdate>(ctx, *reader, on_update);
}

v1::MapInfo Client::LoadMap(const std::string& path) {
  v1::LoadMapRequest req;
  req.set_path(path);
  return Call(*mapping_, &v1::MappingService::Stub::LoadMap, req).info();
}

v1::NavigationResult Client::ReadMission(grpc::ClientContext&,
                                         grpc::ClientReaderInterface<v1::NavigateToResponse>& reader,
                                         const FeedbackCallback& on_feedback, double timeout,
                                         const ScheduleCallback& on_schedule) const {
  v1::NavigateToResponse msg;
  std::optional<v1::NavigationResult> result;
  while (reader.Read(&msg)) {
    if (msg.has_schedule() && on_schedule) on_schedule(msg.schedule());
    if (msg.has_feedback() && on_feedback) on_feedback(msg.feedback());
    if (msg.has_result()) result = msg.result();
  }
  const grpc::Status s = reader.Finish();
  if (!s.ok()) {
    if (s.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED) {
      throw ClientError(s.error_code(),
                        "navigation did not finish within " + std::to_string(timeout) + " s; navd cancelled the goal");
    }
    Fail(s);
  }
  if (!result) throw ClientError(grpc::StatusCode::INTERNAL, "navd ended the navigation stream without a result");
  return *result;
}

v1::NavigationResult Client::NavigateTo(const v1::NavigateToRequest& request, const FeedbackCallback& on_feedback,
                                        double timeout) {
  grpc::ClientContext ctx;
  Prepare(ctx, timeout);
  auto reader = navigation_->NavigateTo(&ctx, request);
  return ReadMission(ctx, *reader, on_feedback, timeout);
}

v1::NavigationResult Client::FollowWaypoints(const v1::FollowWaypointsRequest& request,
                                             const FeedbackCallback& on_feedback, double timeout) {
  grpc::ClientContext ctx;
  Prepare(ctx, timeout);
  auto reader = navigation_->FollowWaypoints(&ctx, request);
  return ReadMission(ctx, *reader, on_feedback, timeout);
}

v1::NavigationResult Client::Deliver(const v1::DeliverRequest& request, const ScheduleCallback& on_schedule,
                                     const FeedbackCallback& on_feedback, double timeout) {
  grpc::ClientContext ctx;
  Prepare(ctx, timeout);
  auto reader = navigation_->Deliver(&ctx, request);
  return ReadMission(ctx, *reader, on_feedback, timeout, on_schedule);
}

v1::DeliverySchedule Client::PlanDeliveries(const v1::DeliverRequest& request) {
  return Call(*navigation_, &v1::NavigationService::Stub::PlanDeliveries, request);
}

v1::NavigationResult Client::NavigateTo(double x, double y, std::optional<double> theta,
                                        const FeedbackCallback& on_feedback, double timeout) {
  v1::NavigateToRequest req;
  req.mutable_goal()->set_x(x);
  req.mutable_goal()->set_y(y);
  if (theta) {
    req.mutable_goal()->set_theta(*theta);
    req.set_use_goal_heading(true);
  }
  return NavigateTo(req, on_feedback, timeout);
}

bool Client::Cancel() {
  return Call(*navigation_, &v1::NavigationService::Stub::Cancel, v1::CancelRequest()).was_active();
}

void Client::Pause() { Call(*navigation_, &v1::NavigationService::Stub::Pause, v1::PauseRequest()); }

void Client::Resume() { Call(*navigation_, &v1::NavigationService::Stub::Resume, v1::ResumeRequest()); }

v1::GetStatusResponse Client::GetStatus() {
  return Call(*navigation_, &v1::NavigationService::Stub::GetStatus, v1::GetStatusRequest());
}

v1::SpeedZones Client::SetSpeedZones(const v1::SetSpeedZonesRequest& request) {
  return Call(*navigation_, &v1::NavigationService::Stub::SetSpeedZones, request);
}

v1::SpeedZones Client::GetSpeedZones() {
  return Call(*navigation_, &v1::NavigationService::Stub::GetSpeedZones, v1::GetSpeedZonesRequest());
}

OccupancyGrid ToOccupancyGrid(const v1::GetMapResponse& map) {
  const v1::MapInfo& info = map.info();
  OccupancyGrid grid(static_cast<int>(info.width()), static_cast<int>(info.height()), info.resolution(),
                     Point2(info.origin().x(), info.origin().y()), OccupancyGrid::kUnknown);
  const std::string& cells = map.cells();
  for (int y = 0; y < grid.height(); ++y)
    for (int x = 0; x < grid.width(); ++x) {
      const size_t i = grid.Flat({x, y});
      if (i < cells.size()) grid.set({x, y}, static_cast<int8_t>(cells[i]));
    }
  return grid;
}

}  // namespace navd
