#pragma once
// Which pairing of a log's scans with its ODOM lines (services/common/carmen_odometry.h) its own
// scans agree with. Loggers write a scan and the odometry of the same moment differently, and
// stamps do not always tell (fake or repeated stamps, a scan stamped like the ODOM line before it
// yet moving with the one after it); a scan paired with the wrong line errs by the motion between
// the two (0.1-0.3 rad while turning), beyond what a SLAM front end's window or a particle
// filter's motion noise expects. So consecutive scans are matched against each other, and the
// candidate pairing whose odometry steps come nearest the matched steps, at the median over the
// log, is the log's pairing. Scanner frame, metres, radians.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "services/common/carmen_log.h"
#include "services/common/carmen_odometry.h"
#include "services/common/odometry_noise.h"
#include "services/common/scan_reach.h"
#include "services/mapping/point_to_line_matcher.h"

namespace navd::mapping {

struct OdometryPairingOptions {
  int max_pairs = 120;  // consecutive scan pairs matched, spread evenly over the log
  // Pairs whose candidates differ less than this (the robot stood still or drove straight at an
  // even speed) say nothing about the pairing and are left out.
  double min_spread_xy = 0.02;     // m
  double min_spread_theta = 0.02;  // rad
  // The match's window: the candidates' spread around the middle one and this much more; pairs
  // whose candidates spread wider than the cap are left out.
  double margin_xy = 0.2;         // m
  double margin_theta = 0.1;      // rad
  double max_window_xy = 1.0;     // m
  double max_window_theta = 0.6;  // rad
  ScanReachOptions reach;         // how far each scan's returns are used
  double point_spacing = 0.1;     // m between the later scan's points matched
  int min_points = 20;            // fewer returns in either scan: the pair is left out
  // One scan as the reference has gaps between its far points that a local map would fill, so
  // its matches score lower than the front end's; this keeps out only those that fit nothing.
  double min_score = 0.2;  // correlative mean lookup, 0..1
  // The correlative pose is polished point to line (PointToLineMatcher, as the SLAM front end
  // does), the polish held loosely to it; a polish moving it farther than this paired points
  // with the wrong walls, and the correlative pose stands.
  PointToLineOptions polish = [] {
    PointToLineOptions p;
    p.prior_sigma_xy = 0.3;
    return p;
  }();
  double polish_max_shift_xy = 0.05;     // m
  double polish_max_shift_theta = 0.03;  // rad
  // A step's disagreement: the distance between the two steps' translations plus this many metres
  // per radian between their turns (a heading error of 0.01 rad moves a wall 10 m off by 0.1 m).
  double metres_per_radian = 1.0;
  int min_pairs = 10;  // fewer scored pairs: the default pairing stands
};

// The pairings chosen among: by stamp, and by file place 0, 1/4, 1/2, 3/4 and 1.
std::vector<OdometryPairing> OdometryPairingCandidates();

struct OdometryPairingEstimate {
  OdometryPairing pairing;  // the chosen one (the default when the log cannot tell)
  bool given = false;       // asked for, not estimated
  bool decided = false;     // estimated from at least min_pairs scored pairs
  int pairs = 0;            // scan pairs matched and scored
  // With stamped ODOM lines: each candidate of OdometryPairingCandidates() with its median
  // disagreement (m) over the pairs (0 when none was scored).
  std::vector<OdometryPairing> candidates;
  std::vector<double> disagreement;
};

// The pairing for `log`'s stamped ODOM lines. A log without them keeps the default (its scans'
// own odometry fields, whatever the pairing) and no scan is matched.
OdometryPairingEstimate EstimateOdometryPairing(const CarmenLog& log, const OdometryPairingOptions& options = {});

// One line for people: the pairing chosen, from how many pairs, and each candidate's disagreement.
std::string Summary(const OdometryPairingEstimate& estimate);

// The log's odometry at each scan (OdometryAtScans), paired as `given` says, or without it as
// its scans agree; `estimate`, when given, is told how (no candidates when nothing was matched).
std::vector<Pose2> PairedOdometryAtScans(const CarmenLog& log, const std::optional<OdometryPairing>& given = {},
                                         OdometryPairingEstimate* estimate = nullptr);

// Where a replay's odometry comes from: the log's corrected poses corrupted by a seeded noise
// model (the evaluation protocol), or the odometry the log holds (a raw robot log).
enum class OdometrySource { kNoisy, kLog };

// The odometry a replay of `log` gives at each scan. kLog: PairedOdometryAtScans with `given`, and
// `how` (when given) receives the pairing's Summary(); kNoisy: NoisyOdometryAtScans with `noise`
// and `seed`, and `how` is left alone.
std::vector<Pose2> ReplayOdometryAtScans(const CarmenLog& log, OdometrySource source,
                                         const std::optional<OdometryPairing>& given, const OdometryNoise& noise,
                                         uint64_t seed, std::string* how = nullptr);

}  // namespace navd::mapping
