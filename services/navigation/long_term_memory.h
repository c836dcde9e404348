#pragma once
// Seed 000's long-term memory (section 4.6) as a cognitive process: a newly served map (a map
// being built, one loaded by a client) is handed to the localisers. A localiser's model of a large
// map (likelihood field, ray caster) takes up to a second to build, so the hand-over runs on a
// worker thread, not in a control step, and the localisers go on with the old map until it is
// ready.
#include <atomic>
#include <cstdint>
#include <future>

#include "services/common/map_store.h"
#include "services/localization/localizer.h"

namespace navd::navigation {

class LongTermMemory {
 public:
  // The localiser was built on the map `maps` serves now.
  LongTermMemory(const MapStore& maps, localization::Localizer& localizer);

  // One step: collects a finished hand-over, and starts one when the served map is newer than
  // the localiser's. Control thread.
  void Step();
  // The served map's version the localiser matches scans against; 0 while a hand-over is under
  // way. Control thread.
  uint64_t localizer_map_version() const;

 private:
  const MapStore& maps_;
  localization::Localizer& localizer_;
  std::atomic<uint64_t> version_{0};
  // The hand-over under way: the map version it hands over, 0 if it failed.
  std::future<uint64_t> handover_;
};

}  // namespace navd::navigation
