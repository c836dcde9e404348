#pragma once
// Publishes navd's map on rt/<ns>/map from its own thread, paced in wall time: the map being
// built every `building_period` seconds during a mapping run, otherwise the served map when it
// changes and every `served_period` seconds (for late joiners). The costmap navd plans on
// (SensedCostmap) goes out on rt/<ns>/navd/costmap likewise, at most every `costmap_period`
// seconds while it changes. Rendering and sending a large map
// takes tens of milliseconds, which the control loop must not spend, and simulated time may run
// many times faster than the wall.
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "server/dds_bridge.h"
#include "services/common/map_store.h"
#include "server/sensed_costmap.h"
#include "services/mapping/map_builder.h"

namespace navd::server {

class MapPublisher {
 public:
  MapPublisher(DdsBridge& bridge, const MapStore& maps, const mapping::MapBuilder& builder, const Clock& clock,
               SensedCostmap& costmaps, double building_period = 2.0, double served_period = 30.0,
               double costmap_period = 1.0);
  ~MapPublisher();
  void Start();
  void Stop();

 private:
  void Run();
  // The costmap as it is now, in Nav2's published scale, when it changed or is due again.
  void PublishCostmap(bool due);

  DdsBridge& bridge_;
  const MapStore& maps_;
  const mapping::MapBuilder& builder_;
  const Clock& clock_;
  SensedCostmap& costmaps_;
  double building_period_, served_period_, costmap_period_;
  std::shared_ptr<const planning::Costmap> costmap_;  // the last one published
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace navd::server
