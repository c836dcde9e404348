#pragma once
// Seed 000's localisation watch, a cognitive process: it tells a lost pose estimate from a few
// scans that fit poorly, and, while the wake-up behaviour has the robot, runs the search that finds
// the pose again (first nearby, then over the whole map). The executive reads lost() as the state
// variable localization_lost. Map frame, metres, radians, seconds of the daemon's clock.
#include <atomic>
#include <cstdint>
#include <optional>

#include "services/common/pose2.h"
#include "services/localization/localizer.h"

namespace navd::navigation {

// When the pose estimate counts as lost: the scan fits the map worse than lost_quality (the
// localiser's 0..1 agreement, the mean per-beam likelihood ratio) for lost_after seconds and for
// lost_scans scans in a row (when the caller counts scans: one poor scan of a sparse log, 3 s
// before the next, is not a lost robot). Found
// again once the fit is back above found_quality with the position spread under max_spread.
// Measured agreement: at true poses 0.99 in navsim's warehouse, 0.94 median and 0.43 at the 1st
// percentile on the real Intel log; at wrong poses in the warehouse 0.15 median, 0.48 at most
// (200 random pairs).
// The wake-up searches first around where the robot was lost (the last pose that fitted, carried
// on by odometry; a Gaussian of search_sigma_xy, search_sigma_theta), for local_search_for
// seconds, and only then over the whole map as seed 000 proposes, again every
// global_search_every seconds while still lost: most losses are short (walkers crowding the
// laser, a door opened) and the pose is still near, and along a featureless street or corridor a
// global search cannot tell places apart at all; a robot carried far away is found by the global
// search after. Where the localiser can (Localizer::StartSearch), the whole-map search runs beside
// the estimate, which goes on tracking, and replaces it only once it fits as a found pose does
// (found_quality, max_spread) for lost_scans scans: on the Intel log the pose was declared lost
// where the scans fitted poorly at a right pose, and a search in its place settled in the wrong
// room (whole-log RMSE 6.7-6.9 m; beside, 0.08 m).
// With search_ahead the search beside begins at the first poorly fitting scan, not once the loss
// is declared, and ends once the estimate fits as a found pose does: a laser that scans once
// every few seconds (a log that keeps a scan per metre driven) takes lost_scans scans to declare
// the loss and as many for the search to be believed, and the two no longer come one after the
// other. A poor scan among people costs a search that ends at the next scan that fits well; a
// search is adopted only once the loss is declared, by the same rule as before.
struct LocalizationWatchOptions {
  double lost_quality = 0.45;
  double lost_after = 3.0;  // s
  int lost_scans = 3;
  // Well above lost_quality: after a loss, on real logs, a corridor seen the other way round or a
  // look-alike stretch fits at 0.6-0.7 for scans in a row (a true pose at 0.94 median).
  double found_quality = 0.8;
  double max_spread = 0.3;            // m, sqrt(var x + var y)
  double search_turn_rate = 0.5;      // rad/s: the wake-up behaviour turns in place while it searches
  double search_sigma_xy = 0.2;       // m: the spread stays within max_spread along a featureless way
  double search_sigma_theta = 0.3;    // rad
  double local_search_for = 15.0;     // s: a full turn at search_turn_rate, and some; 0: global at once
  double global_search_every = 30.0;  // s
  bool search_ahead = true;
};

class LocalizationWatch {
 public:
  LocalizationWatch(localization::Localizer& localizer, const LocalizationWatchOptions& options);

  // Updates lost() from the estimate, and remembers the last pose that fitted. `odometry`: the
  // robot's odometry pose at the estimate's stamp, if known; `scans`: scans arrived so far (0: not
  // counted).
  void Watch(const localization::PoseEstimate& estimate, const std::optional<Pose2>& odometry, uint64_t scans,
             double now);
  // The wake-up's search for a lost pose: begins once the wake-up has the robot (`wake_up_active`),
  // first nearby, then over the whole map (beside the estimate where the localiser can; one still
  // settling is left to settle, one whose last scan fitted as a found pose does is left to
  // confirm, one settled where it does not fit starts again). Ends the search
  // once the pose is found.
  void Search(const localization::PoseEstimate& estimate, const std::optional<Pose2>& odometry, bool wake_up_active,
              double now);

  bool lost() const { return lost_; }
  // Times the pose has been lost: declared lost here, or relocated by the localiser on its own.
  uint64_t losses() const { return losses_; }
  bool searching_nearby() const { return search_ == Stage::kNearby; }
  const LocalizationWatchOptions& options() const { return options_; }

 private:
  enum class Stage { kNone, kNearby, kGlobal };
  // Counts the scans in a row in which the search beside fitted as a found pose does (clears
  // search_beside_ when someone else ended it); `settling`: still spread over the map.
  void CountSearchFits(bool* settling);

  localization::Localizer& localizer_;
  LocalizationWatchOptions options_;
  double poor_fit_since_ = -1.0;
  int poor_scans_ = 0;  // scans in a row that fitted poorly
  uint64_t last_scans_ = 0;
  uint64_t relocations_seen_ = 0;  // the localiser's count, at the last watch
  // The last pose that fitted the scans, and the odometry then (for where the search begins).
  std::optional<Pose2> fit_pose_, fit_odometry_;
  Stage search_ = Stage::kNone;    // of the current loss
  double global_search_at_ = 0.0;  // when the next global search begins
  // The global search runs beside the estimate (Localizer::StartSearch), which goes on tracking:
  // scans in a row in which it fitted as a found pose does, and the stamp of the last one.
  bool search_beside_ = false;
  int search_fits_ = 0;
  double search_stamp_ = -1.0;
  bool fits_as_found_ = false;       // the last estimate fitted as a found pose does
  std::atomic<bool> lost_{false};    // read by gRPC threads
  std::atomic<uint64_t> losses_{0};  // likewise
};

}  // namespace navd::navigation
