#pragma once
// The depth camera in the control loop: the newest cloud, when one arrived since the last tick,
// goes into the obstacle layer, placed by the localiser's pose carried by the odometry to the cloud's own stamp
// (at 1 rad/s the robot turns 0.07 rad in the 67 ms between frames: 0.3 m at 4 m). The layer
// follows the served map: a new map starts it afresh.
#include <memory>
#include <vector>

#include "server/dds_bridge.h"
#include "services/common/map_store.h"
#include "services/localization/localizer.h"
#include "services/perception/depth_obstacle_layer.h"

namespace navd::server {

class CameraPerception {
 public:
  CameraPerception(DdsBridge& bridge, const MapStore& maps, const localization::Localizer& localizer,
                   perception::DepthObstacleLayer& layer);
  // Control thread, once a tick at clock time `now`: the newest cloud, if a new one came, into the
  // layer. Returns the layer's cells (map frame).
  std::shared_ptr<const std::vector<Point2>> Step(double now);

 private:
  DdsBridge& bridge_;
  const MapStore& maps_;
  const localization::Localizer& localizer_;
  perception::DepthObstacleLayer& layer_;
  uint64_t clouds_seen_ = 0;
  uint64_t map_version_ = 0;
};

}  // namespace navd::server
