#include "services/navigation/people_tracking.h"

namespace navd::navigation {

PeopleTracking::PeopleTracking(const PeopleAwareOptions& options)
    : options_(options), segmenter_(options.detection), tracker_(options.tracking), reported_(options.tracking) {}

void PeopleTracking::SetMapFromOdometry(const Pose2& map_from_odometry) {
  std::lock_guard<std::mutex> lock(mutex_);
  map_from_odometry_ = map_from_odometry;
}

void PeopleTracking::TrackScan(const localization::ScanReading& scan, const Pose2& pose, double now,
                               const std::shared_ptr<const RayCaster>& map) {
  if (!map) return;
  segmenter_.SetMap(map);
  const std::vector<DetectedObstacle> blobs = segmenter_.Segment(scan, pose);
  std::lock_guard<std::mutex> lock(mutex_);
  const Pose2 odometry_from_map = map_from_odometry_.inverse();
  std::vector<Point2> seen;
  for (const DetectedObstacle& blob : blobs)
    if (blob.radius <= options_.max_person_radius) seen.push_back(odometry_from_map * blob.position);
  tracker_.Update(seen, now);
}

void PeopleTracking::Report(const PeopleReport& report, const std::optional<Pose2>& robot_odometry, const Pose2& robot,
                            double seen_at) {
  std::lock_guard<std::mutex> lock(mutex_);
  reported_.Update(report, robot_odometry ? *robot_odometry : map_from_odometry_.inverse() * robot, seen_at);
}

void PeopleTracking::Reset() {
  std::lock_guard<std::mutex> lock(mutex_);
  tracker_.Reset();
  reported_.Reset();
}

std::vector<TrackedPerson> PeopleTracking::People(double now) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<TrackedPerson> people =
      options_.source == PeopleAwareOptions::Source::kReports ? reported_.People(now) : tracker_.People(now);
  const Pose2& to_map = map_from_odometry_;
  for (TrackedPerson& p : people) {
    p.position = to_map * p.position;
    p.velocity = Rotate(p.velocity, to_map.theta);
    p.orientation = NormalizeAngle(p.orientation + to_map.theta);
  }
  return people;
}

bool PeopleTracking::empty() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return tracker_.tracks().empty() && reported_.empty();
}

}  // namespace navd::navigation
