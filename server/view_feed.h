#pragma once
// navd's live view (navd --view HOST:PORT): a Foxglove WebSocket server with the built-in page,
// fed from its own thread at `rate` Hz of wall time with snapshots of what navd knows: the served
// map and the map being built, the costmap, the pose estimate with covariance (and the map ->
// base_link transform), the leg's path as planned and ahead of the robot, the newest scan, tracked
// people and moving obstacles, the executive's status and the mission's progress. The control loop
// is not involved: the feed reads the same thread-safe snapshots the gRPC handlers read, and a
// channel nobody subscribes to is not even encoded.
//
// Clients with the command access may publish on "/goal" (navd.Goal {x, y[, yaw]} in the map
// frame, or a geometry_msgs/PoseStamped-like {pose: {position, orientation}}) to start a
// navigation goal, preempting the active one, and on "/cancel" to cancel it; the answer comes back
// as a status message to that client.
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>

#include "server/dds_bridge.h"
#include "services/common/map_store.h"
#include "services/localization/localizer_selector.h"
#include "services/mapping/map_builder.h"
#include "services/navigation/navigation_executive.h"
#include "server/sensed_costmap.h"
#include "services/planning/planning_engine.h"
#include "view/foxglove_server.h"

namespace navd::server {

struct ViewFeedOptions {
  view::FoxgloveServerOptions server;
  double rate = 10.0;       // Hz of wall time
  double map_period = 2.0;  // s: the map being built, during a mapping run
  std::string robot_frame = "base_link";
};

// What the feed reads; all of it outlives the feed.
struct ViewSources {
  const MapStore& maps;
  const mapping::MapBuilder& builder;
  planning::PlanningEngine& planning;
  SensedCostmap& costmaps;  // what /costmap shows: the planner's, with the sensed obstacles
  const localization::LocalizerSelector& localizer;
  navigation::NavigationExecutive& executive;
  const DdsBridge* bridge = nullptr;  // the newest scan; null: no scan channel data
  const Clock& clock;
};

class ViewFeed {
 public:
  ViewFeed(ViewFeedOptions options, ViewSources sources);
  ~ViewFeed();
  // Throws navd::Error when the listener cannot start (view::FoxgloveServer::Start).
  void Start();
  void Stop();
  int port() const { return server_.port(); }

 private:
  struct Channels {
    uint32_t map, map_building, costmap, pose, transform, path, path_ahead, scan, people, obstacles, status, mission;
  };
  void Run();
  void PublishOnce(bool building_due);
  // The served map when it changed, the one being built when due, the costmap when rebuilt.
  void PublishMaps(bool building_due, uint64_t stamp, double now);
  // The pose with its covariance, and the map -> robot transform.
  void PublishPose(const localization::PoseEstimate& estimate, uint64_t stamp);
  // What the robot senses: the newest scan, the people it tracks, the moving obstacles it avoids.
  void PublishSensed(const navigation::NavigationStatus& s, uint64_t stamp, double now);
  void Command(const view::ClientMessage& m);

  ViewFeedOptions options_;
  ViewSources sources_;
  view::FoxgloveServer server_;
  Channels channels_{};
  uint64_t map_version_ = 0;
  std::shared_ptr<const planning::Costmap> costmap_;  // the last one shown
  uint64_t status_sequence_ = 0;
  uint64_t scans_seen_ = 0;

  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::deque<view::ClientMessage> commands_;  // from clients, run on the feed's thread
  std::thread thread_;
};

}  // namespace navd::server
