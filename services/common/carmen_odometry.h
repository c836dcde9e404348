#pragma once
// The odometry a CARMEN log holds, at each of its scans: what a robot's own wheels said, for SLAM
// and localisation on raw logs (no corrected poses). Metres, radians, the odometry's own frame.
#include <optional>
#include <string>
#include <vector>

#include <cstdint>

#include "services/common/carmen_log.h"
#include "services/common/odometry_noise.h"

namespace navd {

// How a scan is paired with the log's stamped ODOM lines. Loggers differ: in the public CARMEN
// logs a scan shares its stamp with the ODOM line before it, yet moves with the one after it
// (the odometry was read later than the scan's stamp says), while a logger that stamps both at
// the time of reading puts the scan between its neighbours by stamp. mapping/odometry_pairing.h
// tells which from the scans themselves.
struct OdometryPairing {
  // true: interpolated between the last stamped ODOM line before the scan in the file and the
  // first after it when their stamps bracket the scan's, else the one nearer in stamp (the one
  // before on a tie, so logs with repeated or fake stamps follow the file).
  bool by_stamp = true;
  // With by_stamp false: the share of the way from the line before the scan (0) to the line after
  // it (1). It applies where those two are stamped at most max_gap apart and no other scan lies
  // between them; across a longer gap in the odometry (a stalled stream, the robot turning on the
  // spot meanwhile), or for scans sharing their two lines (a laser faster than the odometry), the
  // stamp rule above does.
  double position = 0.0;
  double max_gap = 1.0;  // s
};
std::string Describe(const OdometryPairing& pairing);
// A pairing as people write it: "stamp", or a share of the way (0 to 1); "auto" (nullopt): let
// the scans tell (mapping/odometry_pairing.h). Throws navd::Error naming `field` otherwise.
std::optional<OdometryPairing> ParseOdometryPairing(const std::string& text, const std::string& field);

// One odometry pose per scan, in the log's scan order (file order). With ODOM lines, each scan
// takes the stamped ODOM lines next to it in the file (the last before it and the first after
// it) as `pairing` says. ODOM lines stamped 0 or less carry no time and are left out (corrected
// logs echo their corrected pose that way). Without ODOM lines, each scan's own odometry fields
// (FLASER odom_x odom_y odom_theta). Those are the robot centre's; each is carried forward by
// the log's front_laser_offset to the scanner, whose motion the scans show (turning on the
// spot, a scanner 0.2 m ahead moves 0.28 m per quarter turn while the centre stays).
std::vector<Pose2> OdometryAtScans(const CarmenLog& log, const OdometryPairing& pairing = {});
// Whether the log has stamped ODOM lines (else the pairing makes no difference).
bool HasStampedOdometry(const CarmenLog& log);

// The evaluation protocol for corrected logs: each scan's corrected pose, corrupted step by step
// by the seeded noise model of odometry_noise.h. One pose per scan, in scan order.
std::vector<Pose2> NoisyOdometryAtScans(const CarmenLog& log, const OdometryNoise& noise, uint64_t seed);

}  // namespace navd
