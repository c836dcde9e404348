#include "services/navigation/localization_watch.h"

#include <algorithm>

namespace navd::navigation {

LocalizationWatch::LocalizationWatch(localization::Localizer& localizer, const LocalizationWatchOptions& options)
    : localizer_(localizer), options_(options) {}

void LocalizationWatch::Watch(const localization::PoseEstimate& e, const std::optional<Pose2>& odometry, uint64_t scans,
                              double now) {
  const double spread = e.PositionSpread();
  const bool new_scan = scans != last_scans_;
  last_scans_ = scans;
  if (e.relocations != relocations_seen_) {
    if (e.relocations > relocations_seen_ && !lost_) ++losses_;
    relocations_seen_ = e.relocations;
  }
  fits_as_found_ = e.quality >= options_.found_quality && spread <= options_.max_spread;
  if (lost_) {
    if (fits_as_found_) lost_ = false;
    poor_fit_since_ = -1.0;
    poor_scans_ = 0;
    return;
  }
  if (e.quality < options_.lost_quality) {
    if (poor_fit_since_ < 0.0) poor_fit_since_ = now;
    if (new_scan) ++poor_scans_;
    if (options_.search_ahead && !search_beside_ && (new_scan || now == poor_fit_since_)) {
      search_beside_ = localizer_.StartSearch();
      search_fits_ = 0;
    }
    const bool enough_scans = scans == 0 || poor_scans_ >= options_.lost_scans;
    if (now - poor_fit_since_ >= options_.lost_after && enough_scans) {
      lost_ = true;
      ++losses_;
    }
  } else {
    poor_fit_since_ = -1.0;
    poor_scans_ = 0;
    fit_pose_ = e.pose;
    fit_odometry_ = odometry;
  }
}

void LocalizationWatch::CountSearchFits(bool* settling) {
  *settling = false;
  if (!search_beside_) return;
  // Scans the search used: one stamp each.
  const localization::PoseEstimate found = localizer_.SearchEstimate();
  if (!found.valid) {
    search_beside_ = false;  // ended by someone else (a pose set, a new map)
    search_fits_ = 0;
    return;
  }
  if (found.stamp != search_stamp_) {
    search_stamp_ = found.stamp;
    const bool fits = found.quality >= options_.found_quality && found.PositionSpread() <= options_.max_spread;
    search_fits_ = fits ? search_fits_ + 1 : 0;
  }
  *settling = found.PositionSpread() > options_.max_spread;
}

void LocalizationWatch::Search(const localization::PoseEstimate& estimate, const std::optional<Pose2>& odometry,
                               bool wake_up_active, double now) {
  bool search_settling = false;
  if (!lost_) {
    search_ = Stage::kNone;
    if (search_beside_ && !fits_as_found_) {
      CountSearchFits(&search_settling);  // begun ahead of a loss that may come
    } else if (search_beside_) {
      localizer_.EndSearch(false);  // found by the estimate itself, or it fits well again
      search_beside_ = false;
    }
    return;
  }
  // The whole-map search replaces the estimate only once it fits as a found pose does, for
  // lost_scans scans in a row.
  CountSearchFits(&search_settling);
  if (search_beside_ && search_fits_ >= std::max(1, options_.lost_scans)) {
    localizer_.EndSearch(true);
    search_beside_ = false;
    return;
  }
  if (search_ == Stage::kNone) {
    if (!wake_up_active) return;
    Pose2 centre = estimate.pose;
    if (fit_pose_ && fit_odometry_ && odometry) centre = *fit_pose_ * (fit_odometry_->inverse() * *odometry);
    const double sxy = options_.search_sigma_xy, st = options_.search_sigma_theta;
    if (options_.local_search_for > 0.0 &&
        localizer_.SearchAround(centre, Eigen::Vector3d(sxy * sxy, sxy * sxy, st * st).asDiagonal())) {
      search_ = Stage::kNearby;
      global_search_at_ = now + options_.local_search_for;
      // A robot carried away is not near: the whole map is searched beside from the start (or
      // since the first poor scan, where the search went ahead).
      if (!search_beside_) {
        search_beside_ = localizer_.StartSearch();
        search_fits_ = 0;
      }
      return;
    }
  } else if (now < global_search_at_) {
    return;
  } else if (search_settling || (search_beside_ && search_fits_ > 0)) {
    // Still spread over the map, or settled where its last scan fitted as a found pose does: let
    // it settle or confirm rather than scatter it again.
    global_search_at_ = now + options_.global_search_every;
    return;
  }
  search_beside_ = localizer_.StartSearch();
  search_fits_ = 0;
  if (!search_beside_) localizer_.GlobalRelocalize();
  search_ = Stage::kGlobal;
  global_search_at_ = now + options_.global_search_every;
}

}  // namespace navd::navigation
