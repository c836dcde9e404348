#pragma once
// The sonar ring of a Pioneer 2/3 (seeds 002 and 004): 16 Polaroid transducers on the rim, 8
// facing forward and to the sides, 8 backward and to the sides, each a 15 degree cone reading
// 0.1-5 m from the rim. The simulator's ring and navd's sonar reflexes share this table, since the
// Range messages carry only the sensor's frame id (sonar_<i>), not where it points. Radians, robot
// frame (x forward, counter-clockwise); metres.
#include <cmath>
#include <vector>

namespace navd {

// Mounting angle of sonar i, i = 0..15: 90, 50, 30, 10, -10, -30, -50, -90, -90, -130, -150, -170,
// 170, 150, 130, 90 degrees (two sensors on each side, as on the real robot).
const std::vector<double>& PioneerSonarAngles();
inline constexpr double kPioneerSonarCone = 15.0 * M_PI / 180.0;  // rad, full opening
inline constexpr double kPioneerSonarRangeMin = 0.10;             // m
inline constexpr double kPioneerSonarRangeMax = 5.0;              // m

}  // namespace navd
