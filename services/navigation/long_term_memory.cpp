#include "services/navigation/long_term_memory.h"

#include <chrono>
#include <system_error>

namespace navd::navigation {

LongTermMemory::LongTermMemory(const MapStore& maps, localization::Localizer& localizer)
    : maps_(maps), localizer_(localizer) {
  if (const auto map = maps_.Get()) version_ = map->version;
}

void LongTermMemory::Step() {
  if (handover_.valid()) {
    if (handover_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
    const uint64_t handed = handover_.get();
    if (handed > 0) version_ = handed;  // 0: it failed, and is tried again
  }
  const auto map = maps_.Get();
  if (!map || map->version == version_) return;
  try {
    handover_ = std::async(std::launch::async, [this, map]() -> uint64_t {
      try {
        localizer_.SetMap(map->grid);
        return map->version;
      } catch (const std::exception&) {
        return 0;  // out of memory, say: the old map stays
      }
    });
  } catch (const std::system_error&) {
    // No thread to be had now; the next step tries again.
  }
}

uint64_t LongTermMemory::localizer_map_version() const {
  const bool busy = handover_.valid() && handover_.wait_for(std::chrono::seconds(0)) != std::future_status::ready;
  return busy ? 0 : version_.load();
}

}  // namespace navd::navigation
