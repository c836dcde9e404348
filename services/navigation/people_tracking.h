#pragma once
// Book chapter 7's people, as a cognitive process: the laser's blobs that the map does not explain
// and that are a person's size are tracked as people (PersonTracker), or a people detector's
// reports are kept (ReportedPeople). Both are kept in the odometry frame, which does not jump when
// the localiser corrects itself, and read in the map frame. Written by the control thread, read by
// gRPC and telemetry threads: thread-safe.
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "services/navigation/crowd_controller.h"
#include "services/navigation/moving_obstacle_detector.h"
#include "services/navigation/person_tracker.h"
#include "services/navigation/reported_people.h"

namespace navd::navigation {

// Book chapter 7 among people: the laser's blobs that the map does not explain are tracked as
// people (PersonTracker), and while a leg is driven the crowd controller (its RRT in a
// model-predictive loop) steers along the leg's path round them, minimising the time spent in
// their personal space. The seed-000 avoidance behaviour and the moving-obstacle speed guard then
// leave people to it (the laser's stopping guard stays). Off by default: navd --people-aware.
struct PeopleAwareOptions {
  bool enabled = false;
  // Where the people come from: the laser's blobs through the person tracker, or the reports of a
  // people detector or tracker (ExecutiveInputs::people; book chapter 7's simulations give the
  // robot every person's position and velocity so).
  enum class Source { kLaser, kReports };
  Source source = Source::kLaser;
  // Which blobs are people: Segment() of the moving-obstacle detector, out to max_distance, with
  // no margin; wider ones are something else.
  MovingObstacleDetectorOptions detection = [] {
    MovingObstacleDetectorOptions d;
    d.max_distance = 12.0;
    d.margin = 0.0;
    d.max_radius = 1.0;
    return d;
  }();
  double max_person_radius = 0.45;  // m
  double person_radius = 0.25;      // m: each tracked person's disc in the plans
  PersonTrackerOptions tracking;
  CrowdControllerOptions control;
};

class PeopleTracking {
 public:
  explicit PeopleTracking(const PeopleAwareOptions& options);

  // Where the odometry frame lies in the map frame now: the estimate times the inverse of the
  // odometry pose at its stamp.
  void SetMapFromOdometry(const Pose2& map_from_odometry);
  // The people a scan taken at `pose` (map frame) shows, against the served map's caster `map`.
  void TrackScan(const localization::ScanReading& scan, const Pose2& pose, double now,
                 const std::shared_ptr<const RayCaster>& map);
  // A people report seen at `seen_at` (s, this clock), from the robot at odometry pose
  // `robot_odometry` (when the report says), else at map pose `robot`.
  void Report(const PeopleReport& report, const std::optional<Pose2>& robot_odometry, const Pose2& robot,
              double seen_at);
  void Reset();

  // The people at `now`, map frame.
  std::vector<TrackedPerson> People(double now) const;
  bool empty() const;
  const PeopleAwareOptions& options() const { return options_; }

 private:
  PeopleAwareOptions options_;
  MovingObstacleDetector segmenter_;
  mutable std::mutex mutex_;
  PersonTracker tracker_;    // guarded by mutex_; odometry frame
  ReportedPeople reported_;  // likewise
  Pose2 map_from_odometry_;  // guarded by mutex_; identity without odometry
};

}  // namespace navd::navigation
