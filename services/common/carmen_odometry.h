#pragma once
// The odometry a CARMEN log holds, at each of its scans: what a robot's own wheels said, for SLAM
// and localisation on raw logs (no corrected poses). Metres, radians, the odometry's own frame.
#include <vector>

#include <cstdint>

#include "services/common/carmen_log.h"
#include "services/common/odometry_noise.h"

namespace navd {

// One odometry pose per scan, in the log's scan order (file order). With ODOM lines, each scan
// takes the ODOM lines next to it in the file (the last before it and the first after it):
// interpolated by stamp when their stamps bracket the scan's, else the one nearer in stamp (the
// one before on a tie, so logs with repeated or fake stamps follow the file). ODOM lines stamped
// 0 or less carry no time and are left out (corrected logs echo their corrected pose that way).
// Without ODOM lines, each scan's own odometry fields (FLASER odom_x odom_y odom_theta). Those are
// the robot centre's; each is carried forward by the log's front_laser_offset to the scanner,
// whose motion the scans show (turning on the spot, a scanner 0.2 m ahead moves 0.28 m per
// quarter turn while the centre stays).
std::vector<Pose2> OdometryAtScans(const CarmenLog& log);

// The evaluation protocol for corrected logs: each scan's corrected pose, corrupted step by step
// by the seeded noise model of odometry_noise.h. One pose per scan, in scan order.
std::vector<Pose2> NoisyOdometryAtScans(const CarmenLog& log, const OdometryNoise& noise, uint64_t seed);

}  // namespace navd
