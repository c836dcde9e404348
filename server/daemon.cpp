#include "server/daemon.h"

#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "server/camera_perception.h"
#include "server/control_loop.h"
#include "server/dds_bridge.h"
#include "server/map_publisher.h"
#include "dds/topics.h"
#include "server/security/grpc_security.h"
#include "server/view_feed.h"
#include "services/common/error.h"
#include "services/common/map_store.h"
#include "services/common/sonar_ring.h"
#include "services/common/text_file.h"
#include "services/common/world.h"
#include "services/localization/localization_service.h"
#include "services/localization/ekf_localizer.h"
#include "services/localization/histogram_localizer.h"
#include "services/localization/localizer_selector.h"
#include "services/localization/odometric_calibration.h"
#include "services/localization/odometry_localizer.h"
#include "services/localization/particle_filter.h"
#include "services/mapping/mapping_service.h"
#include "services/mapping/slam_localizer.h"
#include "services/navigation/navigation_executive.h"
#include "services/navigation/navigation_service.h"
#include "services/planning/planner_catalog.h"
#include "services/planning/planning_engine.h"
#include "services/planning/planning_service.h"
#include "view/view_page.h"

namespace navd::server {
namespace {

// The live view of --view, or null for "off". Throws navd::Error naming --view for an address that
// is not HOST:PORT, or one beyond loopback without --insecure (the view is plain HTTP and
// WebSocket: anyone on the path could read the tokens, and without tokens drive the robot).
std::unique_ptr<ViewFeed> MakeViewFeed(const DaemonOptions& o, const security::GrpcSecurity& security,
                                       const ViewSources& sources) {
  if (o.view == "off") return nullptr;
  ViewFeedOptions options;
  view::ParseListenAddress("--view", o.view, options.server);
  if (!security::IsLoopbackAddress(o.view) && !o.grpc_security.insecure) {
    throw Error(ErrorCode::kInvalidArgument, "--view: " + o.view +
                                                 " is beyond loopback and the view is plain text: "
                                                 "add --insecure to serve it there anyway");
  }
  options.server.name = o.robot_namespace.empty() ? "navd" : "navd " + o.robot_namespace;
  options.server.page = view::ViewPage();
  if (security.has_roles()) {
    options.server.access = [&security](std::string_view token) {
      const std::optional<security::Role> role = security.RoleOfToken(token);
      if (!role) return view::Access::kNone;
      return *role >= security::Role::kOperator ? view::Access::kCommand : view::Access::kWatch;
    };
  }
  return std::make_unique<ViewFeed>(std::move(options), sources);
}

// Starts the view. A default address that is taken (another navd on this host) leaves navd without
// one, with a warning; an address asked for with --view must bind.
void StartViewFeed(const DaemonOptions& o, std::unique_ptr<ViewFeed>& view) {
  if (!view) return;
  try {
    view->Start();
  } catch (const Error& e) {
    if (o.view_asked) throw;
    spdlog::warn("navd: {}; running without the live view (choose another with --view HOST:PORT)", e.what());
    view.reset();
    return;
  }
  const std::string host = o.view.substr(0, o.view.rfind(':'));
  if (!o.view_port_file.empty()) WriteFileAtomically(o.view_port_file, std::to_string(view->port()) + "\n");
  spdlog::info("navd: live view at http://{}:{}/ (Foxglove: ws://{}:{})", host, view->port(), host, view->port());
}

// navd's clock: the simulated one of --use-sim-time, which rt/clock sets, or the system's.
struct DaemonClock {
  std::unique_ptr<Clock> clock;
  SimClock* sim = nullptr;  // `clock` under --use-sim-time, else null
};

DaemonClock MakeClock(bool use_sim_time) {
  DaemonClock out;
  if (!use_sim_time) {
    out.clock = std::make_unique<SystemClock>();
    return out;
  }
  auto clock = std::make_unique<SimClock>();
  out.sim = clock.get();
  out.clock = std::move(clock);
  return out;
}

// navd's services on `listen`, with gRPC's standard health service reporting each as serving (and
// the server as a whole, the empty name). `port` is the bound one (--listen may ask for 0). Throws
// navd::Error when the address cannot be bound.
std::unique_ptr<grpc::Server> StartGrpcServer(const std::string& listen, const security::GrpcSecurity& security,
                                              std::initializer_list<grpc::Service*> services, int& port) {
  grpc::EnableDefaultHealthCheckService(true);
  grpc::ServerBuilder builder;
  port = 0;
  builder.AddListeningPort(listen, security.Credentials(), &port);
  for (grpc::Service* service : services) builder.RegisterService(service);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (!server || port == 0) {
    throw Error(ErrorCode::kUnavailable,
                "cannot listen on " + listen +
                    " (address in use or invalid, or a TLS key that does not match its certificate)");
  }
  auto* health = server->GetHealthCheckService();
  for (const char* name : {"", v1::PlanningService::service_full_name(), v1::LocalizationService::service_full_name(),
                           v1::MappingService::service_full_name(), v1::NavigationService::service_full_name()}) {
    health->SetServingStatus(name, true);
  }
  return server;
}

// What navd runs on besides its map: the robot, where it starts, and the world's speed zones and
// depth camera (none of them with --map: the default robot at the map's origin).
struct DaemonSetting {
  RobotDescription robot;
  Pose2 initial_pose;
  std::vector<SpeedZone> speed_zones;
  std::optional<DepthCameraDescription> camera;
};

// Puts the map of --map, or of --world (the embedded one by default), into `maps`. Throws
// navd::Error for an initial pose off the map.
DaemonSetting LoadSetting(const DaemonOptions& o, MapStore& maps) {
  DaemonSetting setting;
  if (!o.map_path.empty()) {
    std::string name;
    OccupancyGrid grid = LoadAnyMapFile(o.map_path, &name);
    maps.Set(std::move(grid), name);
  } else {
    World world = o.world_path.empty() ? DefaultWorld() : LoadWorldFile(o.world_path);
    setting.robot = world.robot;
    setting.initial_pose = world.start;
    setting.speed_zones = std::move(world.speed_zones);
    setting.camera = world.camera;
    maps.Set(std::move(world.map), world.name);
  }
  if (o.initial_pose_set) setting.initial_pose = {o.initial_pose[0], o.initial_pose[1], o.initial_pose[2]};
  const auto map = maps.Get();
  spdlog::info("navd: map '{}' {}x{} cells at {} m", map->name, map->grid.width(), map->grid.height(),
               map->grid.resolution());
  if (!map->grid.ContainsPoint(setting.initial_pose.translation())) {
    throw Error(ErrorCode::kInvalidArgument,
                "initial pose " + FormatPoint(setting.initial_pose.translation()) + " lies outside the map");
  }
  return setting;
}

planning::PlanningEngineOptions PlanningOptions(const DaemonOptions& o, const RobotDescription& robot) {
  planning::PlanningEngineOptions options;
  options.costmap.inflation_radius = robot.radius + o.inflation_margin;
  options.costmap.decay_radius = o.cost_decay;
  options.velocity.max_speed = robot.max_wheel_speed;
  options.velocity.max_acceleration = robot.max_wheel_accel;
  // Opposite rims at full acceleration turn the body at 2 a / wheel base.
  options.velocity.max_angular_acceleration = 2.0 * robot.max_wheel_accel / robot.wheel_base;
  return options;
}

// Every localiser runs; --localizer (or SelectMethod) picks the one that answers.
void AddLocalizers(const DaemonOptions& o, const RobotDescription& robot, const OccupancyGrid& grid,
                   mapping::MapBuilder& map_builder, localization::LocalizerSelector& localizer) {
  localization::ParticleFilterOptions filter_options;
  if (robot.drive == DriveType::kOmni) filter_options.motion_model = localization::MotionModel::kOmni;
  if (o.laser_model == "beam") filter_options.sensor_model = localization::SensorModel::kBeam;
  if (o.odom_alpha > 0.0)
    filter_options.alpha1 = filter_options.alpha2 = filter_options.alpha3 = filter_options.alpha4 = o.odom_alpha;
  if (o.update_min_d > 0.0) filter_options.update_min_distance = o.update_min_d;
  if (o.update_min_a > 0.0) filter_options.update_min_angle = o.update_min_a;
  // The control loop never waits for the nearby reset's search (tens of ms): a scan that comes
  // while it runs is weighed without it.
  filter_options.nearby_reset.wait_for_search = false;
  localizer.Add(std::make_unique<localization::ParticleFilterLocalizer>(grid, filter_options));
  localizer.Add(std::make_unique<localization::OdometryLocalizer>());
  localizer.Add(std::make_unique<localization::EkfLocalizer>(grid));
  localization::OdometricCalibrationOptions calibration;
  calibration.wheel_base = robot.wheel_base;
  localizer.Add(std::make_unique<localization::OdometricCalibrationLocalizer>(grid, calibration));
  // Grid localisation only where its grid is small enough (10 cm x 10 degrees).
  try {
    localizer.Add(std::make_unique<localization::HistogramLocalizer>(grid));
  } catch (const Error& e) {
    if (o.localizer == "histogram") throw;
    spdlog::info("histogram localisation not offered: {}", e.what());
  }
  localizer.Add(std::make_unique<mapping::SlamLocalizer>(map_builder));  // while exploring
  localizer.Select(o.localizer);
}

// --people-aware: the crowd planner's limits are the robot's, and among people at most --crowd-speed.
navigation::PeopleAwareOptions PeopleAwareOptions(const DaemonOptions& o, const RobotDescription& robot) {
  navigation::PeopleAwareOptions people;
  people.enabled = o.people_aware;
  if (o.people_source == "topic" && !o.people_aware)
    spdlog::warn("navd: --people-source topic has no effect without --people-aware");
  people.source = o.people_source == "topic" ? navigation::PeopleAwareOptions::Source::kReports
                                             : navigation::PeopleAwareOptions::Source::kLaser;
  planning::UnicycleLimits& limits = people.control.limits;
  if (robot.drive == DriveType::kUnicycle) {
    limits = {robot.max_speed, robot.max_angular_speed, robot.max_accel, robot.max_angular_accel};
  } else {
    // Opposite rims at full speed (acceleration) turn the body at 2 v / wheel base.
    limits = {robot.max_wheel_speed, 2.0 * robot.max_wheel_speed / robot.wheel_base, robot.max_wheel_accel,
              2.0 * robot.max_wheel_accel / robot.wheel_base};
  }
  // The plans' noise would carry the robot past the desired speed; among people it is a limit.
  limits.max_speed = std::min(o.crowd_speed, limits.max_speed);
  people.control.planner.desired_speed = limits.max_speed;
  people.control.planner.robot_radius = robot.radius;
  if (o.people_aware) {
    spdlog::info("navd: people-aware: crowd RRT at {} m/s, {} vertices per plan every {} s; people from {}",
                 people.control.planner.desired_speed, people.control.planner.max_nodes, people.control.replan_period,
                 o.people_source == "topic" ? "rt/<ns>/people" : "the laser");
  }
  return people;
}

}  // namespace

int RunDaemon(const DaemonOptions& o, DaemonSignals& signals) {
  // Refused before anything starts: a daemon that would listen unprotected must not come up.
  security::GrpcSecurity grpc_security(o.grpc_security, o.listen);
  // --- Map and robot -------------------------------------------------------------------------
  MapStore maps;
  DaemonSetting setting = LoadSetting(o, maps);
  const RobotDescription& robot = setting.robot;
  const auto map = maps.Get();

  // --- Services -----------------------------------------------------------------------------
  planning::PlanningEngine planning(maps, PlanningOptions(o, robot));
  planning::RegisterDefaultPlanners(planning);
  planning.CurrentCostmap();  // built now rather than on the first request
  mapping::MapBuilder map_builder;
  localization::LocalizerSelector localizer(/*search_on_its_own_thread=*/true);
  AddLocalizers(o, robot, map->grid, map_builder, localizer);
  localizer.SetPose(setting.initial_pose, Eigen::Matrix3d::Zero());  // checks it, too

  const DaemonClock daemon_clock = MakeClock(o.use_sim_time);
  Clock* const clock = daemon_clock.clock.get();
  SimClock* const sim_clock = daemon_clock.sim;

  navigation::NavigatorOptions navigator;
  navigator.follower.wheel_base = robot.wheel_base;
  navigator.follower.max_wheel_speed = robot.max_wheel_speed;
  navigator.reflex.enabled = o.sonar_reflexes;
  const navigation::UtilityBrainOptions brain =
      o.brain_path.empty() ? navigation::DefaultBrainOptions() : navigation::LoadBrainFile(o.brain_path);
  navigation::MovingObstacleOptions moving;
  moving.detection.robot_radius = robot.radius;
  moving.avoidance.wheel_base = robot.wheel_base;
  const navigation::PeopleAwareOptions people = PeopleAwareOptions(o, robot);
  navigation::NavigationExecutive executive(planning, localizer, *clock, navigator, brain, {}, moving, people);
  for (const SpeedZone& z : setting.speed_zones)
    spdlog::info("navd: speed zone '{}': at most {} m/s", z.name, z.max_speed);
  executive.SetSpeedZones(navigation::SpeedZones(std::move(setting.speed_zones)));

  // --- Transport ----------------------------------------------------------------------------
  DdsBridge bridge(o.dds, o.robot_namespace, sim_clock, *clock, o.odometry == "encoders" ? &robot : nullptr,
                   o.rear_range_frame,
                   !o.sonar_reflexes        ? std::vector<double>{}
                   : o.sonar_angles.empty() ? PioneerSonarAngles()
                                            : o.sonar_angles,
                   o.people_aware && o.people_source == "topic");
  // The depth camera the world describes, its clouds into an obstacle layer over the served map.
  std::unique_ptr<perception::DepthObstacleLayer> camera_layer;
  std::unique_ptr<CameraPerception> camera_perception;
  if (setting.camera) {
    const auto layer_options = perception::DepthObstacleLayerOptions::ForRobot(robot.height);
    camera_layer = std::make_unique<perception::DepthObstacleLayer>(*setting.camera, layer_options);
    camera_perception = std::make_unique<CameraPerception>(bridge, maps, localizer, *camera_layer);
    spdlog::info("navd: depth camera at {:.2f} m, tilted {:.0f} degrees down: obstacles up to {:.2f} m from {}",
                 setting.camera->mount_z, setting.camera->tilt * 180.0 / M_PI, layer_options.filter.max_height,
                 dds::TopicName(o.robot_namespace, dds::kCameraPoints));
  }
  ControlLoop loop({o.control_rate, o.sensor_timeout, robot.wheel_base}, *clock, bridge, localizer, executive,
                   map_builder, camera_perception.get());
  SensedCostmap costmaps(planning, camera_layer.get());
  MapPublisher map_publisher(bridge, maps, map_builder, *clock, costmaps);
  std::unique_ptr<ViewFeed> view =
      MakeViewFeed(o, grpc_security, {maps, map_builder, planning, costmaps, localizer, executive, &bridge, *clock});

  planning::PlanningService planning_service(planning);
  localization::LocalizationService localization_service(localizer, maps);
  navigation::Explorer explorer(maps, map_builder, executive, planning, localizer, *clock);
  navigation::ExplorerOptions exploring;
  // Exploration goals a little deeper in free space than the planners' inflation: SLAM poses err
  // by a few centimetres.
  exploring.exploration.clearance = robot.radius + o.inflation_margin + 0.05;
  mapping::MappingService mapping_service(maps, map_builder, explorer, exploring,
                                          [&localizer]() -> std::optional<Pose2> {
                                            const localization::PoseEstimate e = localizer.Estimate();
                                            if (!e.valid) return std::nullopt;
                                            return e.pose;
                                          });
  navigation::NavigationService navigation_service(executive);

  int port = 0;
  std::unique_ptr<grpc::Server> server = StartGrpcServer(
      o.listen, grpc_security, {&planning_service, &localization_service, &mapping_service, &navigation_service}, port);
  StartViewFeed(o, view);
  const std::string host = o.listen.substr(0, o.listen.rfind(':'));
  if (!o.port_file.empty()) WriteFileAtomically(o.port_file, std::to_string(port) + "\n");
  loop.Start();
  map_publisher.Start();
  spdlog::info("navd: listening on {}:{} ({}), DDS domain {}, {} clock", host, port, grpc_security.Describe(),
               o.dds.domain, o.use_sim_time ? "simulated (rt/clock)" : "system");
  if (grpc_security.warns_plain_text_beyond_loopback()) {
    spdlog::warn(
        "navd: --insecure: gRPC in plain text on {}, without authentication: anyone who reaches the port "
        "can drive the robot",
        o.listen);
  }

  while (!signals.stop) {
    if (signals.reload_tokens.exchange(false)) grpc_security.ReloadCredentialTable();
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }

  // --- Shutdown: robot first ----------------------------------------------------------------
  spdlog::info("navd: shutting down");
  try {
    explorer.Stop();
  } catch (const Error&) {
    // Not exploring.
  }
  executive.Cancel();
  loop.Stop();  // also publishes a zero command
  map_publisher.Stop();
  if (view) view->Stop();
  server->GetHealthCheckService()->Shutdown();
  server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(2));
  spdlog::info("navd: stopped");
  return 0;
}

}  // namespace navd::server
