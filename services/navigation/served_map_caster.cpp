#include "services/navigation/served_map_caster.h"

namespace navd::navigation {

std::shared_ptr<const RayCaster> ServedMapCaster::Get() const {
  const auto map = maps_.Get();
  if (!map) return nullptr;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!caster_ || map->version != version_) {
    caster_ = std::make_shared<const RayCaster>(map->grid);
    version_ = map->version;
  }
  return caster_;
}

}  // namespace navd::navigation
