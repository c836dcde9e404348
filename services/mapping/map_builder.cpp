#include "services/mapping/map_builder.h"

#include "services/common/error.h"

namespace navd::mapping {

MappingStatus MapBuilder::Start(const MappingSessionOptions& options, const Pose2& start) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (session_ && session_->status().active)
    throw Error(ErrorCode::kFailedPrecondition, "a mapping run is already active: stop it first");
  auto next = std::make_shared<MappingSession>(options, start);  // throws before replacing the last run
  session_ = std::move(next);
  return session_->status();
}

MappingStatus MapBuilder::Stop() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!session_ || !session_->status().active) throw Error(ErrorCode::kFailedPrecondition, "no mapping run is active");
  session_->Finish();
  return session_->status();
}

void MapBuilder::Submit(const Pose2& odometry, const Pose2& localised, const RangeScan& scan) {
  std::shared_ptr<MappingSession> s = session();
  if (s && s->status().active) s->Submit(odometry, localised, scan);
}

bool MapBuilder::active() const {
  const auto s = session();
  return s && s->status().active;
}

std::shared_ptr<MappingSession> MapBuilder::session() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return session_;
}

}  // namespace navd::mapping
