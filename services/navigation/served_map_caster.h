#pragma once
// A RayCaster of the map navd serves now, rebuilt when the served map changes (a map being built,
// a new map loaded): the processes that compare what the sensors see with the map share it.
// Thread-safe.
#include <cstdint>
#include <memory>
#include <mutex>

#include "services/common/map_store.h"
#include "services/common/ray_caster.h"

namespace navd::navigation {

class ServedMapCaster {
 public:
  // The caster of the map served now is built at once rather than at the first scan: on a large
  // map it takes a third of a second, which a control loop would spend while messages pile up.
  explicit ServedMapCaster(const MapStore& maps) : maps_(maps) { Get(); }
  // The caster of the map served now; null before there is one.
  std::shared_ptr<const RayCaster> Get() const;

 private:
  const MapStore& maps_;
  mutable std::mutex mutex_;
  mutable uint64_t version_ = 0;
  mutable std::shared_ptr<const RayCaster> caster_;
};

}  // namespace navd::navigation
