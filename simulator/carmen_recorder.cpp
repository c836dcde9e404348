#include "simulator/carmen_recorder.h"

#include <cerrno>
#include <cstring>
#include <unistd.h>

#include <filesystem>

#include "services/common/error.h"

namespace navd::sim {
namespace {

std::string Fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

std::string PoseFields(const Pose2& p) { return Fixed(p.x, 6) + " " + Fixed(p.y, 6) + " " + Fixed(p.theta, 6); }

// CARMEN lines end with the timestamp, the host name and the logger's timestamp.
std::string Stamp(double t) { return Fixed(t, 6) + " navsim " + Fixed(t, 6); }

}  // namespace

CarmenRecorder::CarmenRecorder(const std::string& path, const std::string& description)
    : path_(path), part_(path + ".part") {
  file_ = std::fopen(part_.c_str(), "w");
  if (!file_) {
    throw Error(ErrorCode::kInvalidArgument, "cannot create log file '" + part_ + "': " + std::strerror(errno));
  }
  Line("# CARMEN log recorded by navsim: " + description);
  Line("# ROBOTLASER1 laser pose = true pose, robot pose = odometry; TRUEPOS = ground truth");
}

CarmenRecorder::~CarmenRecorder() {
  if (file_) {
    try {
      Close();
    } catch (...) {
      // Destructors must not throw; the .part file stays for inspection.
    }
  }
}

void CarmenRecorder::Line(const std::string& line) {
  std::fputs(line.c_str(), file_);
  std::fputc('\n', file_);
}

void CarmenRecorder::Laser(double t, const LaserDescription& laser, double angle_min, double increment,
                           const std::vector<float>& ranges, const Pose2& true_pose, const Pose2& odom_pose, double v,
                           double omega) {
  std::string line = "ROBOTLASER1 0 " + Fixed(angle_min, 6) + " " + Fixed(laser.fov, 6) + " " + Fixed(increment, 8) +
                     " " + Fixed(laser.range_max, 3) + " " + Fixed(laser.noise, 3) + " 0 " +
                     std::to_string(ranges.size());
  line.reserve(line.size() + ranges.size() * 7 + 200);
  for (float r : ranges) {
    line += ' ';
    line += Fixed(r, 3);
  }
  line += " 0 " + PoseFields(true_pose) + " " + PoseFields(odom_pose) + " " + Fixed(v, 4) + " " + Fixed(omega, 4) +
          " 0.0 0.0 0.0 " + Stamp(t);
  Line(line);
}

void CarmenRecorder::Odometry(double t, const Pose2& odom_pose, double v, double omega) {
  Line("ODOM " + PoseFields(odom_pose) + " " + Fixed(v, 4) + " " + Fixed(omega, 4) + " 0.0 " + Stamp(t));
}

void CarmenRecorder::Truth(double t, const Pose2& true_pose, const Pose2& odom_pose) {
  Line("TRUEPOS " + PoseFields(true_pose) + " " + PoseFields(odom_pose) + " " + Stamp(t));
}

void CarmenRecorder::Close() {
  if (!file_) return;
  const bool ok = std::fflush(file_) == 0 && ::fsync(fileno(file_)) == 0;
  std::fclose(file_);
  file_ = nullptr;
  std::error_code ec;
  if (!ok) throw Error(ErrorCode::kInternal, "writing log file '" + part_ + "' failed");
  std::filesystem::rename(part_, path_, ec);
  if (ec) throw Error(ErrorCode::kInternal, "cannot move '" + part_ + "' to '" + path_ + "': " + ec.message());
}

}  // namespace navd::sim
