#include "services/mapping/map_builder.h"

#include "services/common/error.h"

namespace navd::mapping {

MappingStatus MapBuilder::Start(const MappingSessionOptions& options, const Pose2& start) {
  std::shared_ptr<MappingSession> last;  // let go of outside the lock: its end may take a while
  std::shared_ptr<MappingSession> next;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (session_ && session_->status().active)
      throw Error(ErrorCode::kFailedPrecondition, "a mapping run is already active: stop it first");
    next = std::make_shared<MappingSession>(options, start);  // throws before replacing the last run
    last = std::move(session_);
    session_ = next;
  }
  return next->status();
}

MappingStatus MapBuilder::Stop() {
  const std::shared_ptr<MappingSession> s = session();
  if (!s || !s->status().active) throw Error(ErrorCode::kFailedPrecondition, "no mapping run is active");
  // Outside the lock: the control loop keeps submitting (to nobody) while the last scan and the
  // last drawing finish.
  s->Finish();
  return s->status();
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
