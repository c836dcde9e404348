#pragma once
// Records one simulated robot as a CARMEN log, so runs can be replayed (navd-replay) and shared:
// ROBOTLASER1 scans (with their own angles; laser pose = the true pose, as in a "corrected" log;
// robot pose = odometry), ODOM odometry and TRUEPOS ground truth. Lines stream to "<path>.part"
// and the file appears under its name only when Close() renames it: a log is never half-written
// under its final name. Metres, radians, seconds of simulated time.
#include <cstdio>
#include <string>
#include <vector>

#include "services/common/pose2.h"
#include "services/common/world.h"

namespace navd::sim {

class CarmenRecorder {
 public:
  // Throws navd::Error when the file cannot be created.
  CarmenRecorder(const std::string& path, const std::string& description);
  ~CarmenRecorder();
  CarmenRecorder(const CarmenRecorder&) = delete;
  CarmenRecorder& operator=(const CarmenRecorder&) = delete;

  void Laser(double t, const LaserDescription& laser, double angle_min, double increment,
             const std::vector<float>& ranges, const Pose2& true_pose, const Pose2& odom_pose, double v, double omega);
  void Odometry(double t, const Pose2& odom_pose, double v, double omega);
  void Truth(double t, const Pose2& true_pose, const Pose2& odom_pose);
  // Flushes and renames into place. Throws navd::Error when that fails.
  void Close();

 private:
  void Line(const std::string& line);

  std::string path_;
  std::string part_;
  std::FILE* file_ = nullptr;
};

}  // namespace navd::sim
