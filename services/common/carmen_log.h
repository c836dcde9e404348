#pragma once
// Reader of CARMEN logs (the format of the classic public 2-D laser datasets): `FLASER` laser scans
// with the laser's pose (corrected, in "corrected" logs) and odometry pose, `ROBOTLASER1` scans
// (which carry their own angles, as navsim's recorder writes them), `ODOM` odometry, `TRUEPOS`
// ground truth (simulators), the `PARAM robot_frontlaser_offset` and the front laser's
// `PARAM laser_front_laser_fov` and `laser_front_laser_resolution` (FlaserBeams). A log logged without the
// robot's laser messages (no FLASER or ROBOTLASER1 line) has its `RAWLASER1` scans read instead,
// each placed where its ODOM lines put the scanner at its stamp, as a raw log's FLASER lines hold
// the odometry's pose. A scan written twice, as a FLASER and a ROBOTLASER1 line of one stamp (the
// front laser's old and new messages), is read once, from the ROBOTLASER1 line. Other messages (a
// rear laser's RLASER among them) are passed over. Plain or gzip-compressed.
// FLASER lines carry no angles: the log's PARAM lines or else their beam count say them
// (FlaserBeams, CarmenBeamAngle). Metres, radians, seconds.
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "services/common/pose2.h"

namespace navd {

struct CarmenScan {
  std::vector<float> ranges;
  double angle_min = 0.0;        // rad, laser frame, beam 0
  double angle_increment = 0.0;  // rad between beams
  double range_max = 0.0;        // m: readings here or beyond are no-returns; 0: none known
  Pose2 pose;                    // laser pose (corrected poses in corrected logs)
  Pose2 odometry;                // odometry pose at the scan
  double timestamp = 0.0;
  int line = 0;
  // range_max as a threshold: infinity when no no-return reading is known.
  double no_return_range() const { return range_max > 0.0 ? range_max : std::numeric_limits<double>::infinity(); }
};

struct CarmenOdometry {
  Pose2 pose;
  double timestamp = 0.0;
  int line = 0;
};

struct CarmenTruth {
  Pose2 pose;      // true pose
  Pose2 odometry;  // odometry pose at the same time
  double timestamp = 0.0;
  int line = 0;
};

// The most beams a scan line may hold: more is a corrupt line, not a scanner.
constexpr int kMaxScanBeams = 100000;

// A front laser's field of view (rad) to the hundredth of a degree, as a log's PARAM line says it
// and the reader takes it: radians written to five decimals (3.14159) are the 180 degrees they round to.
inline double FovRoundedToHundredthOfDegree(double fov) {
  const double degrees = std::round(fov * 180.0 / M_PI * 100.0) / 100.0;
  return degrees * M_PI / 180.0;
}

struct CarmenLog {
  std::vector<CarmenScan> scans;
  std::vector<CarmenOdometry> odometry;
  std::vector<CarmenTruth> truth;
  // m ahead of the robot's centre, where FLASER's scanner sits (PARAM robot_frontlaser_offset; 0
  // when the log does not say): its scans' origin, while ODOM lines and FLASER's odom fields are
  // the centre's.
  double front_laser_offset = 0.0;
  // rad: the front laser's field of view and beam spacing as its PARAM lines state them (0 when
  // the log does not say); FLASER scans' beams are placed by them (FlaserBeams).
  double front_laser_fov = 0.0;
  double front_laser_resolution = 0.0;
  int skipped_lines = 0;  // malformed lines skipped (when not strict)
};

// FLASER lines do not say the scanner's maximum range, and each scanner writes its no-return
// reading differently (81.83, 81.91, 50, 51.1-51.16 in the public logs). The reader infers it: when
// the log's longest reading, within kNoReturnBand of it, repeats in at least kNoReturnMinShare of
// all readings (and kNoReturnMinCount times), readings at or above kNoReturnBand x the longest are
// no-returns. Real echoes never pile up at one far range; saturated ones do. 0 when no such pile
// exists (every reading is then an echo), or when the longest reading is under kNoReturnShortest
// (no 2-D scanner's maximum is that short: such a pile is a wall). Scans that carry their own
// range_max keep it.
constexpr double kNoReturnBand = 0.99;
constexpr double kNoReturnShortest = 4.0;  // m
constexpr double kNoReturnMinShare = 0.0005;
constexpr size_t kNoReturnMinCount = 5;
double InferNoReturnRange(const CarmenLog& log);

// Reads `path` (".gz" or plain). FLASER scans get the inferred no-return range as range_max.
// Malformed scan, ODOM and TRUEPOS lines (and a PARAM robot_frontlaser_offset that is no number
// or farther than 10 m, a laser_front_laser_fov that is no field of view, radians up to 2 pi or
// degrees from 7 to 360, or a laser_front_laser_resolution that is not within (0, 45] degrees)
// throw navd::Error naming the file, line and message (and PARAM's parameter) when `strict`, else
// are skipped and counted. Unknown
// message types are ignored. A log without scans, or whose RAWLASER1 scans have no stamped ODOM
// line to place them, throws navd::Error.
CarmenLog ReadCarmenLog(const std::string& path, bool strict = false);
// The same from text already in memory (`source` names it in errors).
CarmenLog ParseCarmenLog(const std::string& text, const std::string& source, bool strict = false);

// Some logs print their stamps too coarsely to time anything by (csail-corrected.log writes them
// with six significant digits: two distinct values over 406 scans). When fewer than half of the
// scans come later than the scan before, this replaces the scan stamps by times paced from the
// log's own odometry, from the first scan's stamp on: each scan follows the one before after the
// time its motion takes at `speed` m/s or `turn_rate` rad/s, whichever is longer, and at least
// `min_gap` s. Returns whether it did. Scans only: ODOM and TRUEPOS lines keep their stamps.
bool PaceScansWhenStampsAreCoarse(CarmenLog& log, double speed = 0.5, double turn_rate = 0.5, double min_gap = 0.2);

// A few logs stamp a scan earlier than the one before it now and then, or so soon after it that
// the robot would have turned faster than any robot turns (intel-corrected.log: four scans stamped
// back by up to 0.86 s, seven turning half a radian in 10-20 ms). Scans are in the order of their
// place in the file, and a scan comes no sooner after the one before than its motion takes at
// `max_speed` m/s and `max_turn_rate` rad/s (and at least `gap` s): such a scan is re-stamped that
// late, so whatever times by the stamps (a replay, a daemon's odometry checks) sees a robot move as
// robots do. Returns how many scans it re-stamped. Scans only.
int TimeScansInFileOrder(CarmenLog& log, double max_speed = 3.0, double max_turn_rate = 4.0, double gap = 0.001);

// One FLASER line (newline-terminated) that ReadCarmenLog reads back as `scan`: ranges to the
// millimetre, laser pose, odometry pose and stamp (also as the logger's stamp), written by `host`.
// FLASER carries no angles: throws navd::Error (kInvalidArgument) unless the scan's beams lie where
// FlaserBeams puts them for the log's front laser `fov` and `resolution` (rad, 0: not said).
std::string FormatFlaserLine(const CarmenScan& scan, const std::string& host, double fov = 0.0,
                             double resolution = 0.0);
// `log` as text ReadCarmenLog reads back: its front laser's PARAM lines when it states them, then
// a FLASER line for each scan (FormatFlaserLine, which throws for beams they do not place).
std::string FormatFlaserLog(const CarmenLog& log, const std::string& host);

// Beam i of an n-beam FLASER scan, in rad in the laser frame (x ahead, counter-clockwise). FLASER
// carries no angles, so the count says them, as CARMEN's own reader guesses them for a SICK:
// 180 or 181 beams step by 1 degree and 360 or 361 by 0.5 from -90; 400 or 401 beams are the
// scanner's 100-degree mode, 0.25 degrees apart and centred ahead; any other count spreads 180
// degrees from -90 over its n - 1 gaps.
inline double CarmenBeamAngle(size_t i, size_t n) {
  double start = -M_PI / 2, increment = 0.0;
  if (n == 180 || n == 181) {
    increment = M_PI / 180;
  } else if (n == 360 || n == 361) {
    increment = M_PI / 360;
  } else if (n == 400 || n == 401) {
    increment = M_PI / 720;
    start = -0.5 * increment * (n - 1);
  } else if (n > 1) {
    increment = M_PI / static_cast<double>(n - 1);
  }
  return start + static_cast<double>(i) * increment;
}

// Where an n-beam FLASER scan's beams lie, rad in the laser frame: beam 0's angle and the step.
struct FlaserBeamLayout {
  double angle_min = 0.0;
  double angle_increment = 0.0;
};
// CARMEN's laser driver starts a scan at -fov / 2 and steps by the resolution, and a log may say
// both (`PARAM laser_front_laser_fov`, `laser_front_laser_resolution`): a scanner other than a
// 180-degree SICK (a Hokuyo's 240 degrees, a 270-degree or a whole-turn scanner) writes FLASER
// lines that only these place. `fov` and `resolution` in rad, 0 when not said. Without a fov the
// beam count says (CarmenBeamAngle): a resolution alone cannot tell where the beams start. With
// one, beams step by the resolution from -fov / 2 when n beams that far apart span the fov (or the
// fov less one beam); otherwise a 180-degree fov leaves it to the count (which knows the SICK's
// modes), and any other spreads the fov evenly over the n - 1 gaps, or n for a whole turn.
FlaserBeamLayout FlaserBeams(size_t n, double fov = 0.0, double resolution = 0.0);
// The gaps between n beams spread over `fov` (rad): n - 1, or n for a scanner sweeping a whole
// turn, since none of its beams reads one bearing twice.
inline size_t FlaserBeamGaps(size_t n, double fov) { return fov > 2.0 * M_PI - 1e-9 ? n : (n > 0 ? n - 1 : 0); }

}  // namespace navd
