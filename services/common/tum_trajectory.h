#pragma once
// Trajectories in the TUM RGB-D benchmark's text format, one pose per line: "t x y z qx qy qz qw"
// (seconds; metres; a unit quaternion), as evo and the SLAM benchmarks read them. navd's poses are
// planar: z = 0 and the quaternion turns about the vertical axis only.
#include <string>
#include <vector>

#include "services/common/pose2.h"

namespace navd {

// One line, newline included: stamp (s) and pose (x, y in metres, theta in rad, any frame).
std::string FormatTumLine(double stamp, const Pose2& pose);

// One pose per line of `text` that is neither blank nor a comment (#), in order; the heading is the
// quaternion's yaw. Throws std::runtime_error naming `source` and the line number for a line that
// is not eight numbers or whose pose is not finite.
std::vector<Pose2> ParseTumTrajectory(const std::string& text, const std::string& source);

// ParseTumTrajectory of a file; `what` names its role in a missing or unreadable file's message
// (navd::Error, as ReadTextFile).
std::vector<Pose2> ReadTumTrajectory(const std::string& path, const std::string& what);

}  // namespace navd
