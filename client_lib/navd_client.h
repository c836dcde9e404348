#pragma once
// libnavclient: a synchronous C++ client of navd's gRPC API. Every call has a deadline (seconds)
// and throws navd::ClientError carrying the gRPC status code and navd's message on failure.
// Poses and points are in the map frame, metres and radians.
#include <grpcpp/grpcpp.h>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "grpc/health/v1/health.grpc.pb.h"
#include "navd/v1/localization.grpc.pb.h"
#include "navd/v1/mapping.grpc.pb.h"
#include "navd/v1/navigation.grpc.pb.h"
#include "navd/v1/planning.grpc.pb.h"
#include "services/common/occupancy_grid.h"

namespace navd {

class ClientError : public std::runtime_error {
 public:
  ClientError(grpc::StatusCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  grpc::StatusCode code() const { return code_; }

 private:
  grpc::StatusCode code_;
};

struct ClientOptions {
  ClientOptions(std::string server_address = "127.0.0.1:50051", double deadline = 10.0)
      : server(std::move(server_address)), timeout(deadline) {}

  std::string server;
  double timeout;  // default deadline of unary calls, seconds
  // TLS is on when tls_ca or tls_cert is set. tls_ca: PEM CA that signed navd's certificate
  // (empty: the system's roots); tls_cert + tls_key: this client's certificate, for mutual TLS.
  std::string tls_ca;
  std::string tls_cert;
  std::string tls_key;
  std::string tls_server_name;  // the name navd's certificate must carry, when not the address's host
  std::string token;            // sent as "authorization: Bearer <token>"; needs TLS
};

class Client {
 public:
  explicit Client(const ClientOptions& options = {});

  // Blocks until the channel connects or `timeout` passes; returns whether it connected.
  bool WaitForConnected(double timeout);
  // grpc.health.v1 status of `service` ("" = the whole server).
  grpc::health::v1::HealthCheckResponse::ServingStatus Health(const std::string& service = "");

  // `moving`: people and moving obstacles for the planners that plan around them.
  v1::ComputePathResponse ComputePath(double start_x, double start_y, double goal_x, double goal_y,
                                      const std::string& planner = "",
                                      const std::map<std::string, double>& options = {},
                                      const std::vector<v1::MovingBody>& moving = {});
  // start = (x, y); waypoints visited in order, the last being the goal.
  v1::ComputePathResponse ComputePathThroughPoses(double start_x, double start_y,
                                                  const std::vector<std::pair<double, double>>& waypoints,
                                                  const std::string& planner = "");
  v1::ListPlannersResponse ListPlanners();

  v1::GetPoseResponse GetPose();
  void SetPose(double x, double y, double theta);
  void GlobalRelocalize();
  v1::ListMethodsResponse ListMethods();
  void SelectMethod(const std::string& method);
  // Streams pose estimates at `rate_hz` to `on_pose` until it returns false or `timeout` passes.
  void StreamPose(double rate_hz, const std::function<bool(const v1::GetPoseResponse&)>& on_pose, double timeout);

  // The whole map (its chunks joined): the served map, or the mapping run's.
  v1::GetMapResponse GetMap(bool info_only = false, v1::MapSource source = v1::MAP_SOURCE_SERVED);
  v1::SaveMapResponse SaveMap(const std::string& path, v1::MapFormat format = v1::MAP_FORMAT_MAP_SERVER,
                              v1::MapSource source = v1::MAP_SOURCE_SERVED);
  v1::MappingStatus StartMapping(v1::MappingMode mode = v1::MAPPING_MODE_SLAM, double resolution = 0.0,
                                 double size = 0.0);
  v1::MappingStatus StopMapping(bool serve = false);
  v1::MappingStatus GetMappingStatus();
  v1::ExplorationStatus StartExploration(const v1::StartExplorationRequest& request);
  v1::ExplorationStatus StopExploration();
  v1::ExplorationStatus GetExplorationStatus();
  // Calls `on_update` with each changed region until it returns false, the run ends or `timeout`.
  void StreamMapUpdates(double min_period, const std::function<bool(const v1::MapUpdate&)>& on_update, double timeout);
  v1::MapInfo LoadMap(const std::string& path);

  using FeedbackCallback = std::function<void(const v1::NavigationFeedback&)>;
  // Sends the robot to `request.goal` and blocks until the goal ends, calling `on_feedback` for
  // each feedback message. `timeout` bounds the whole navigation (0: none); when it passes, navd
  // cancels the goal and this throws with DEADLINE_EXCEEDED.
  v1::NavigationResult NavigateTo(const v1::NavigateToRequest& request, const FeedbackCallback& on_feedback = {},
                                  double timeout = 0.0);
  // Convenience: goal (x, y), and heading theta when given.
  v1::NavigationResult NavigateTo(double x, double y, std::optional<double> theta = std::nullopt,
                                  const FeedbackCallback& on_feedback = {}, double timeout = 0.0);
  // A waypoint mission (FollowWaypoints); blocks like NavigateTo until the mission ends.
  v1::NavigationResult FollowWaypoints(const v1::FollowWaypointsRequest& request,
                                       const FeedbackCallback& on_feedback = {}, double timeout = 0.0);
  // A delivery mission (Deliver): `on_schedule` gets navd's schedule first; then as FollowWaypoints.
  using ScheduleCallback = std::function<void(const v1::DeliverySchedule&)>;
  v1::NavigationResult Deliver(const v1::DeliverRequest& request, const ScheduleCallback& on_schedule,
                               const FeedbackCallback& on_feedback = {}, double timeout = 0.0);
  // The schedule Deliver would drive, without moving the robot.
  v1::DeliverySchedule PlanDeliveries(const v1::DeliverRequest& request);
  bool Cancel();
  void Pause();
  void Resume();
  v1::GetStatusResponse GetStatus();
  // Replaces navd's speed zones (an empty request clears them); returns them as navd holds them.
  v1::SpeedZones SetSpeedZones(const v1::SetSpeedZonesRequest& request);
  v1::SpeedZones GetSpeedZones();

  const std::string& server() const { return options_.server; }

 private:
  void Prepare(grpc::ClientContext& context, double timeout) const;
  // One unary call with the default deadline; throws ClientError on failure.
  template <typename Stub, typename Request, typename Response>
  Response Call(Stub& stub, grpc::Status (Stub::*method)(grpc::ClientContext*, const Request&, Response*),
                const Request& request) const {
    grpc::ClientContext context;
    Prepare(context, options_.timeout);
    Response response;
    const grpc::Status status = (stub.*method)(&context, request, &response);
    if (!status.ok()) Fail(status);
    return response;
  }
  // Reads a server stream into `on_message` until it returns false (the call is cancelled), the
  // stream ends or its deadline passes; other failures throw ClientError.
  template <typename Message, typename Reader, typename OnMessage>
  void ReadWatch(grpc::ClientContext& context, Reader& reader, const OnMessage& on_message) const {
    Message message;
    while (reader.Read(&message)) {
      if (!on_message(message)) {
        context.TryCancel();
        break;
      }
    }
    const grpc::Status s = reader.Finish();
    if (!s.ok() && s.error_code() != grpc::StatusCode::CANCELLED &&
        s.error_code() != grpc::StatusCode::DEADLINE_EXCEEDED)
      Fail(s);
  }
  [[noreturn]] void Fail(const grpc::Status& status) const;
  // Reads a mission's feedback stream to its result.
  v1::NavigationResult ReadMission(grpc::ClientContext& context,
                                   grpc::ClientReaderInterface<v1::NavigateToResponse>& reader,
                                   const FeedbackCallback& on_feedback, double timeout,
                                   const ScheduleCallback& on_schedule = {}) const;

  ClientOptions options_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<grpc::health::v1::Health::Stub> health_;
  std::unique_ptr<v1::PlanningService::Stub> planning_;
  std::unique_ptr<v1::LocalizationService::Stub> localization_;
  std::unique_ptr<v1::MappingService::Stub> mapping_;
  std::unique_ptr<v1::NavigationService::Stub> navigation_;
};

// The grid of a GetMap answer (its chunks joined), as navd's OccupancyGrid.
OccupancyGrid ToOccupancyGrid(const v1::GetMapResponse& map);

}  // namespace navd
