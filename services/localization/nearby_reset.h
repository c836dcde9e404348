#pragma once
// Sensor resetting within reach (after Lenser and Veloso, "Sensor resetting localization for poorly
// modeled mobile robots", ICRA 2000): when a scan fits the estimate poorly, a correlative search of
// the scan around the estimate; a pose there that the scan fits decisively better is where a share
// of the particles is drawn, and the next scans choose between it and the cloud. A robot carried or
// pushed a few metres, or a cloud left a few metres behind along a corridor, fits again within a
// scan or two, long before the fit is poor for long enough to call the pose lost; where the place
// is ambiguous (a featureless corridor), no pose fits decisively better and nothing is drawn.
// Units: metres, radians; poses in the map frame, scan points in the robot frame.
#include <cmath>
#include <optional>
#include <vector>

#include "services/common/pose2.h"
#include "services/localization/global_scan_search.h"

namespace navd::localization {

struct NearbyResetOptions {
  bool enabled = true;
  // The estimate's fit (the filter's quality, 0..1) under which the search runs. A well-localised
  // estimate fits real scans at 0.9 and more; a robot carried a few metres along a corridor still
  // fits them at 0.85 or so where it was, as the corridor's walls look alike.
  double below_quality = 0.9;
  double radius = 5.0;     // m around the estimate
  double max_turn = M_PI;  // rad either side of its heading: a robot carried off may be turned too
  // A pose is drawn around only if the scan fits it at least this well, and its misfit (1 - score,
  // scores of GlobalScanSearch::Score) there is at most misfit_ratio of the estimate's. Real scans
  // fit their true pose at 0.9 and more; a map that lacks a wall lets a wrong pose fit at 0.7 or so.
  // A ratio, not a difference: near a good fit scores differ little, and a scan that fits the
  // estimate at 0.88 and its true pose 3 m on at 0.96 has a third of the misfit there.
  double min_score = 0.85;
  double misfit_ratio = 0.5;
  // Another pose the scan fits at min_score or better, rival_distance (m) or rival_turn (rad) from
  // the best, is a rival: a later scan chooses between them. The max_rivals best are kept.
  double rival_distance = 1.0;
  double rival_turn = 0.3;
  int max_rivals = 5;
  // Clutter is not a lost pose: people, carts and boxes in front of the walls make a right
  // estimate fit poorly, and a search among look-alike racks then finds a wrong pose that fits
  // better, but from the right estimate the scan passes through no wall. A pose is drawn around
  // only when fewer of the scan's beams pass through a wall from it than from the estimate
  // (GlobalScanSearch::SeeThrough, by more than see_through_margin); a scan that passes through
  // none from the estimate is not searched with. A pose awaiting confirmation is looked for all
  // the same (the scan that found it contradicted the estimate; along a corridor the next one may
  // not), and confirmed where no more beams pass through a wall from it than from the estimate.
  double see_through_margin = 0.15;  // m
  double share = 0.1;                // of the particles drawn around it (shared out when several are)
  double sigma_xy = 0.1, sigma_theta = 0.05;
  int blocks_refined = 30;  // coarse places searched finely (GlobalScanSearch)
  // Whether the next scan waits for a search still running (each run the same, as offline
  // evaluation needs) or is weighed without it (a control loop that must not stall: the search's
  // pose is carried on by the odometry to the first scan after it ends).
  bool wait_for_search = true;
  // Only a pose lost suddenly is searched for: within this many scans of one that fitted at
  // good_quality or better since the pose was last set. A pose told wrong, or one lost long ago,
  // is left to the wake-up's searches, which look beyond the few metres where a warehouse's
  // look-alike racks may fit as well as the true one.
  int within_scans = 10;
  double good_quality = 0.8;
  // A pose farther than relocated_jump from the estimate is drawn around only once a later scan
  // fits it (ConfirmWhereCarried), or a second search finds it again, within this much of where
  // the odometry since has carried it (m, rad), plus confirm_xy_per_metre of the straight-line
  // distance between the two odometry poses: each search's heading is good to a few hundredths of
  // a radian, and a search that takes seconds while the robot drives on finds the pose metres on.
  double confirm_xy = 0.3, confirm_theta = 0.15;
  double confirm_xy_per_metre = 0.1;
  double confirm_theta_per_metre = 0.05;  // rad: the odometry's heading drifts as it goes too
  // The searches after it are centred on where it should be once that is out of the estimate's
  // reach (a lost estimate runs off meanwhile); a pose they find elsewhere awaits confirmation in
  // its place, and after this many of them find nothing, it is forgotten.
  int confirm_searches = 3;
  // The search takes a scan or two while the robot drives on, and its pose, carried on by the
  // odometry to the scan that takes it, drifts with the odometry and the search's own heading
  // error: that scan is searched for it again within this much (m, rad) before the particles are
  // drawn.
  double carried_xy = 0.5, carried_theta = 0.15;
  // An estimate that comes near (within relocated_jump m and relocated_turn rad) a pose drawn away
  // from it, within relocated_scans of the draw (the pose carried on by the odometry), has been
  // relocated. With several poses drawn, the cloud may settle on one a scan or two later; a robot
  // carried off facing the other way may be found where the estimate, running on, passes by.
  double relocated_jump = 0.5;
  double relocated_turn = 0.5;
  int relocated_scans = 3;
};

class NearbyReset {
 public:
  explicit NearbyReset(const NearbyResetOptions& options = {}) : o_(options) {}
  const NearbyResetOptions& options() const { return o_; }
  // Where a pose found away from the estimate should be found again: carried on by the odometry,
  // within tolerance_xy (m) and tolerance_theta (rad).
  struct Expected {
    Pose2 pose;
    double tolerance_xy = 0.0, tolerance_theta = 0.0;
  };
  // A search's find: the pose the scan fits best, and the other poses it fits nearly as well
  // (look-alike places along a corridor), for a later scan to choose between.
  struct Found {
    PoseCandidate best;
    std::vector<PoseCandidate> rivals;
  };
  // Where a share of the particles should go for a scan with `points` whose estimate is
  // `estimate` and fits at `quality`, if anywhere: searched within `radius` of the estimate, or of
  // `expected` (a pose awaiting confirmation) once that is out of the estimate's reach.
  std::optional<Found> Check(const GlobalScanSearch& search, const Pose2& estimate, double quality,
                             const std::vector<Point2>& points, const Expected* expected = nullptr) const;
  // Where a pose `found` by a search at odometry `found_at` should be found by one at odometry
  // `now`: tolerances confirm_xy and confirm_theta, plus confirm_xy_per_metre and
  // confirm_theta_per_metre of the distance between the two.
  Expected Expect(const Pose2& found, const Pose2& found_at, const Pose2& now) const;
  // Whether two poses are within relocated_jump and relocated_turn of each other.
  bool Near(const Pose2& a, const Pose2& b) const { return PosesWithin(a, b, o_.relocated_jump, o_.relocated_turn); }
  // Whether `found` confirms the pose `expected`.
  bool Confirms(const Expected& expected, const Pose2& found) const;
  // Which poses of `found` (searched at odometry `found_at`) a later scan with `points`, at
  // odometry `now`, confirms without another search: where the odometry has carried them, the
  // scan fits them as a search's find must (min_score, and misfit_ratio of its misfit at
  // `estimate`, through no more walls than from there); of those, the best, and beside it every
  // other that the best does not fit decisively better (misfit_ratio), for the next scans to
  // choose between. Empty when the scan fits none.
  std::vector<Pose2> ConfirmWhereCarried(const GlobalScanSearch& search, const Found& found, const Pose2& found_at,
                                         const Pose2& now, const Pose2& estimate,
                                         const std::vector<Point2>& points) const;
  // `carried` (a found pose carried on by the odometry to a later scan with `points`) where that
  // scan fits best within carried_xy and carried_theta, or `carried` if it fits nowhere there.
  Pose2 Settle(const GlobalScanSearch& search, const Pose2& carried, const std::vector<Point2>& points) const;

 private:
  // Whether two poses are less than `xy` metres and `theta` radians apart.
  static bool PosesWithin(const Pose2& a, const Pose2& b, double xy, double theta) {
    return Distance(a.translation(), b.translation()) < xy && std::abs(NormalizeAngle(a.theta - b.theta)) < theta;
  }
  NearbyResetOptions o_;
};

}  // namespace navd::localization
