#pragma once
// The front end's answer to odometry that errs by more than its window: wheels slipping, a log
// whose stamps cannot pair its odometry lines with its scans (0.2-0.4 rad between a tenth of the
// csail log's scans, however its lines are paired). A front-end match that explains little of the local map is
// searched again over a window several times wider; a wider fit that scores clearly better and
// lies beyond the first window either corrects the odometry or is a fit of the wrong place (a
// scan whose own stamp or pose is off, a room seen from its middle turned by a few tens of
// degrees). The two read alike on one scan and differ on the next: after a real odometry error
// the next scan needs the same correction, after a stray fit it matches where the odometry puts
// it. So a far wider fit holds its scan back (no node) and the next scan confirms it: matched
// around its own prediction moved by the same correction, it takes that pose, and the held scan
// its wider fit; otherwise the held scan is dropped (left to odometry). After max_held scans held
// in a row the wider fit is taken as it is (odometry that keeps erring).
//
// The correction is carried in the robot's frame: odometry that lags or leads its scans errs by
// the motion it missed, which the next scan repeats. A slip that turns the odometry once by γ is
// a turn about the place it erred, which the robot-frame correction misses at the next scan by
// 2 d sin(γ/2) for a step of d between them (0.16 m for 0.4 rad over 0.4 m, inside the window);
// on the logs' own odometry the robot frame holds better than the map frame (docs/results.md).
//
// Off in FrontEndRecoveryOptions' defaults: odometry whose error stays inside the window (the
// replay's noise model) gains nothing from it. A robot's own odometry (navd's mapping runs,
// navd-replay --odometry log) takes RobotOdometryRecovery().
// Map frame, metres, radians.
#include <optional>
#include <vector>

#include "services/common/pose2.h"
#include "services/mapping/correlative_scan_matcher.h"

namespace navd::mapping {

struct FrontEndRecoveryOptions {
  // A front-end match scoring below this (mean lookup value, 0..1) is searched again; 0: never.
  double below_score = 0.0;
  // The wider window's half-sizes, its prior widened in proportion (never narrower than the
  // front end's own window).
  double window_xy = 0.6;     // m
  double window_theta = 0.8;  // rad
  // The wider window is searched first with points this far apart and this many times the
  // front end's angular step; only when that pass's best lies beyond the first window is it
  // searched in full.
  double gate_point_spacing = 0.3;  // m
  double gate_angle_step_factor = 4.0;
  // The wider fit must score this much more than the first match.
  double min_gain = 0.05;
  // A wider fit this close to the first match is the same fit, which the first window's prior
  // ranked lower: taken at once.
  double same_xy = 0.1;      // m
  double same_theta = 0.05;  // rad
  int max_held = 2;          // scans held back in a row at most
};

// On for odometry that errs beyond the front end's window at times: a match explaining less than
// 60 % of the local map is searched again. On the csail log's own odometry that takes SLAM from
// metres off to decimetres; on the other CARMEN logs, whose own odometry holds once paired with
// their scans (mapping/odometry_pairing.h), it changes little (docs/results.md).
FrontEndRecoveryOptions RobotOdometryRecovery();

class FrontEndRecovery {
 public:
  // Throws Error(kInvalidArgument) for options that cannot search (a gate step factor below 1, a
  // spacing not above 0, max_held below 0).
  explicit FrontEndRecovery(const FrontEndRecoveryOptions& options);

  struct Outcome {
    ScanMatch match;    // the match to keep (the first one unless recovery replaced it)
    bool held = false;  // the scan is held back: add no node for it
    // This scan confirmed the correction of the scan held just before it: that one's pose.
    std::optional<Pose2> held_fit;
  };

  // `match` is the front end's match of `points` (robot frame) on `local` within `window` around
  // the odometry's prediction `predicted`. Call once per scan the front end matches, in order.
  Outcome Check(const CorrelationGrid& local, const std::vector<Point2>& points, const Pose2& predicted,
                const ScanMatchOptions& window, const ScanMatch& match);

 private:
  Outcome Settle(const ScanMatch& match, bool confirmed = false);

  FrontEndRecoveryOptions o_;
  bool pending_ = false;
  Pose2 pending_correction_;  // the held scan's wider fit in the frame of its prediction
  Pose2 held_fit_;            // the held scan's wider fit, map frame
  int held_ = 0;              // scans held back in a row
};

}  // namespace navd::mapping
