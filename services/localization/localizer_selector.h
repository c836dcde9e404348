#pragma once
// Several localisers run side by side on the same odometry and scans; one of them answers for the
// robot's pose: selected by name at run time, or, with "auto", by the chapter-10 arbiter from the
// context every 0.2 s of sensor time (the book's sampling), switching after ten wins in a row.
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "services/localization/beside_search.h"
#include "services/localization/localizer.h"
#include "services/localization/odometry_jump_filter.h"

namespace navd::localization {

class LocalizerSelector : public Localizer {
 public:
  // search_on_its_own_thread: the whole-map search beside the estimate (StartSearch) weighs scans
  // on a thread of its own (navd), rather than in AddScan (offline replays, tests: deterministic).
  explicit LocalizerSelector(bool search_on_its_own_thread = false)
      : search_on_its_own_thread_(search_on_its_own_thread) {}

  // The first localiser added is selected until Select says otherwise.
  void Add(std::unique_ptr<Localizer> localizer);
  // The localisers' names, then "auto".
  std::vector<std::string> Methods() const;
  // A localiser's name, or "auto" for the arbiter. Throws navd::Error(kInvalidArgument) listing
  // the known methods for an unknown name.
  void Select(const std::string& name);
  bool automatic() const;
  // Weights of the criteria computing time, fault tolerance and precision for "auto": precision
  // first, so the particle filter (CT 2, FT 4) answers unless its scans fit the map poorly
  // (quality below 1/8) and odometry (CT 5, FT 2, precision 2) takes over.
  static constexpr double kWeights[3] = {0.1, 0.3, 0.6};
  static constexpr double kEvaluationPeriod = 0.2;  // s of sensor time
  static constexpr double kLaserTimeout = 1.0;      // s without a scan before the laser counts as gone

  std::string name() const override;  // the selected method's
  // Odometry jumps are taken out first (OdometryJumpFilter) for every localiser.
  void AddOdometry(const OdometryReading& reading) override;
  // Jumps taken out of the odometry so far (navd logs each).
  int odometry_jumps() const;
  bool AddScan(const ScanReading& scan) override;
  PoseEstimate Estimate() const override;
  bool GlobalRelocalize() override;  // on every localiser that can; true if any did
  bool SearchAround(const Pose2& pose, const Eigen::Matrix3d& covariance) override;  // likewise
  bool SetMap(const OccupancyGrid& map) override;  // every localiser's map (and the search's)
  // The search runs beside the selected localiser, on a Fresh() one of its kind (or of the first
  // kind that can) fed the same odometry and scans; SearchEstimate is what it made of the last
  // scan it used, stamped with that scan; adopting it re-anchors every localiser there.
  bool StartSearch() override;
  PoseEstimate SearchEstimate() const override;
  void EndSearch(bool adopt) override;
  MethodContext Suitability(bool laser_fresh) const override { return Selected().Suitability(laser_fresh); }

 private:
  void ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) override;

  // With "auto": scores every localiser and selects the arbiter's choice, at most every
  // kEvaluationPeriod of sensor time.
  void Arbitrate(double stamp);

  std::vector<std::unique_ptr<Localizer>> localizers_;  // fixed after start-up
  OdometryJumpFilter jump_filter_;                      // guarded by mutex_
  std::optional<OdometryReading> last_odometry_;        // guarded by mutex_: a search starts from it
  mutable std::mutex mutex_;
  size_t selected_ = 0;
  // The whole-map search beside the selected localiser, if one runs. Fed outside any lock of
  // ours (a scan on 100 000 particles must hold up neither the selection nor the control loop);
  // shared so that ending it while it is fed is safe.
  const bool search_on_its_own_thread_;
  mutable std::mutex search_mutex_;
  std::shared_ptr<BesideSearch> search_;
  uint64_t map_version_ = 0;  // SetMap calls: a search started on an older map is not kept
  std::shared_ptr<BesideSearch> RunningSearch() const;
  // Held through a re-anchoring (SetPose, adopting a search), so two never interleave.
  std::mutex reset_mutex_;
  void ResetAll(const Pose2& pose, const Eigen::Matrix3d& covariance);
  std::unique_ptr<MethodArbiter> arbiter_;  // set while "auto" is selected
  double last_scan_stamp_ = -1e18, last_evaluation_ = -1e18;
  Localizer& Selected() const;
};

}  // namespace navd::localization
