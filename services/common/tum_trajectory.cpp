#include "services/common/tum_trajectory.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "services/common/text_file.h"

namespace navd {

std::string FormatTumLine(double stamp, const Pose2& pose) {
  char line[160];
  std::snprintf(line, sizeof line, "%.6f %.6f %.6f 0 0 0 %.9f %.9f\n", stamp, pose.x, pose.y, std::sin(pose.theta / 2),
                std::cos(pose.theta / 2));
  return line;
}

std::vector<Pose2> ParseTumTrajectory(const std::string& text, const std::string& source) {
  std::vector<Pose2> poses;
  size_t begin = 0;
  for (int number = 1; begin < text.size(); ++number) {
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(begin, end - begin);
    begin = end + 1;
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    double f[8];
    int used = 0;
    if (std::sscanf(line.c_str(), "%lf %lf %lf %lf %lf %lf %lf %lf %n", &f[0], &f[1], &f[2], &f[3], &f[4], &f[5], &f[6],
                    &f[7], &used) != 8 ||
        line.find_first_not_of(" \t\r", used) != std::string::npos)
      throw std::runtime_error(source + ":" + std::to_string(number) + ": not a TUM pose (t x y z qx qy qz qw)");
    const double qx = f[4], qy = f[5], qz = f[6], qw = f[7];
    const Pose2 pose{f[1], f[2], std::atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))};
    if (!pose.finite()) throw std::runtime_error(source + ":" + std::to_string(number) + ": pose is not finite");
    poses.push_back(pose);
  }
  return poses;
}

std::vector<Pose2> ReadTumTrajectory(const std::string& path, const std::string& what) {
  return ParseTumTrajectory(ReadTextFile(path, what), path);
}

}  // namespace navd
