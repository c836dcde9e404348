#pragma once
// Publishes navd's map on rt/<ns>/map from its own thread, paced in wall time: the map being
// built every `building_period` seconds during a mapping run, otherwise the served map when it
// changes and every `served_period` seconds (for late joiners). Rendering and sending a large map
// takes tens of milliseconds, which the control loop must not spend, and simulated time may run
// many times faster than the wall.
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "server/dds_bridge.h"
#include "services/common/map_store.h"
#include "services/mapping/map_builder.h"

namespace navd::server {

class MapPublisher {
 public:
  MapPublisher(DdsBridge& bridge, const MapStore& maps, const mapping::MapBuilder& builder, const Clock& clock,
               double building_period = 2.0, double served_period = 30.0);
  ~MapPublisher();
  void Start();
  void Stop();

 private:
  void Run();

  DdsBridge& bridge_;
  const MapStore& maps_;
  const mapping::MapBuilder& builder_;
  const Clock& clock_;
  double building_period_, served_period_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace navd::server
