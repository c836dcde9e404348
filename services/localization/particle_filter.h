#pragma once
// Adaptive Monte Carlo localisation, as users know it from ROS's AMCL (Thrun, Burgard and Fox,
// "Probabilistic Robotics", ch. 4 and 8): a particle filter over the robot's map pose with
//  - the odometry motion model (sample_motion_model_odometry, noise alpha1..alpha4; or the
//    omnidirectional variant with alpha5 for sideways slip),
//  - the likelihood-field sensor model on the map's exact distance field (z_hit Gaussian of the
//    distance from a beam's end to the nearest obstacle, plus z_rand), on a subset of beams, or
//    the beam model (ch. 6.3: each beam ray-cast in the map from the particle, a mixture of
//    z_hit N(z - z*), z_short exponential, z_max at no-returns and z_rand), AMCL's "beam",
//  - KLD-sampling to size the particle set to the spread of the belief,
//  - augmented MCL (w_slow, w_fast) to inject uniformly drawn particles when the sensors stop
//    agreeing with the map (recovery from a wrong pose or a kidnapping; off by default),
//  - sensor resetting within reach (NearbyReset): a share of the particles drawn where the scan
//    fits decisively better within a few metres of a poorly fitting estimate.
// Units: metres, radians; poses in the map frame; odometry in the odom frame.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <future>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <vector>

#include "services/common/occupancy_grid.h"
#include "services/common/ray_caster.h"
#include "services/localization/global_scan_search.h"
#include "services/localization/likelihood_field.h"
#include "services/localization/localizer.h"
#include "services/localization/nearby_reset.h"
#include "services/localization/odometry_history.h"
#include "services/localization/scan_points.h"

namespace navd::localization {

// How odometry moves the particles: a differential drive (or unicycle) turns, drives and turns
// (rot1, trans, rot2); an omnidirectional base also slides sideways, so its motion is a
// translation in any direction plus a rotation, with noise of its own across the motion (AMCL's
// "omni" model). Using the diff-drive model for a sideways slide would read it as two quarter
// turns and smear the particles' headings.
enum class MotionModel { kDiffDrive, kOmni };

// How a scan is weighed: against the map's distance field (fast, smooth; AMCL's default) or beam
// by beam against ray casts from each particle (sees no-returns and short readings).
enum class SensorModel { kLikelihoodField, kBeam };

// The beam model's mixture (AMCL's defaults).
struct BeamModelOptions {
  int beams = 30;          // ray casts per particle per scan
  double sigma_hit = 0.2;  // m
  double z_hit = 0.95, z_short = 0.1, z_max = 0.05, z_rand = 0.05;
  double lambda_short = 0.1;  // 1/m
};

struct ParticleFilterOptions {
  MotionModel motion_model = MotionModel::kDiffDrive;
  int min_particles = 500;
  int max_particles = 5000;
  // Scattered for global relocalisation; resampling trims them. 30 000 found 93 of 100 random
  // warehouse poses, 60 000 95-99, 100 000 all (relocalization_bench, seeds 1-3).
  int global_particles = 100000;
  double kld_error = 0.01;                     // KLD bound epsilon
  double kld_z = 2.326;                        // upper standard normal quantile for 1 - delta = 0.99
  double kld_bin_xy = 0.25;                    // m
  double kld_bin_theta = 10.0 * M_PI / 180.0;  // rad
  // Odometry noise (AMCL's odom_alpha1..4): rotation from rotation, rotation from translation,
  // translation from translation, translation from rotation.
  double alpha1 = 0.1, alpha2 = 0.1, alpha3 = 0.1, alpha4 = 0.1;
  double alpha5 = 0.1;  // omni only: sideways slip from translation
  SensorModel sensor_model = SensorModel::kLikelihoodField;
  BeamModelOptions beam_model;
  // Likelihood field.
  int beams = 90;           // beams used per scan, evenly spread
  double sigma_hit = 0.07;  // m
  double z_hit = 0.95;
  double z_rand = 0.05;
  double max_distance = 2.0;  // m: distances beyond count as this far
  double range_max = 4.0;     // m: the z_rand density is 1 / range_max
  // Filter only after the robot moved this much (AMCL update_min_d / update_min_a).
  double update_min_distance = 0.05;  // m
  double update_min_angle = 0.05;     // rad
  // Likelihood exponent during global relocalisation, until the position spread first falls under
  // tempering_spread (metres).
  double tempering = 0.01;
  double tempering_spread = 0.5;
  // Augmented MCL averaging rates (recovery by random particles). Off by default, as in ROS's
  // AMCL (recovery_alpha_* = 0): on real data, people and unmapped clutter lower the fit often
  // enough that injection pulls a well-localised estimate away (Intel log: 0.21 m RMSE with
  // 0.001/0.1, 0.05-0.08 m without). Global relocalisation does not depend on it.
  double alpha_slow = 0.0, alpha_fast = 0.0;
  // Global relocalisation draws its particles around the candidates of a whole-map search of the
  // first scan (GlobalScanSearch) rather than leaving them uniform: on real logs with a scan every
  // few metres, uniform particles take many scans to gather. Spread of the draws around each.
  bool scan_search = true;
  GlobalScanSearchOptions scan_search_options;
  double scan_search_sigma_xy = 0.1, scan_search_sigma_theta = 0.05;
  // Particles drawn where a scan fits decisively better within a few metres of a poorly fitting
  // estimate (searched with scan_search_options' scoring).
  NearbyResetOptions nearby_reset;
  // Initial spread around a SetPose without covariance.
  double initial_sigma_xy = 0.1, initial_sigma_theta = 0.1;
  uint64_t seed = 1;
};

class ParticleFilterLocalizer : public Localizer {
 public:
  ParticleFilterLocalizer(const OccupancyGrid& map, const ParticleFilterOptions& options = {});
  std::string name() const override { return "amcl"; }
  void AddOdometry(const OdometryReading& reading) override;
  bool AddScan(const ScanReading& scan) override;
  // Needs the laser; costlier than odometry, recovers (random particles, relocalisation), and is as
  // precise as its scans fit the map (quality 0..1 as 1..5).
  MethodContext Suitability(bool laser_fresh) const override {
    return {name(), laser_fresh ? 1.0 : 0.0, {2.0, 4.0, 1.0 + 4.0 * std::clamp(Estimate().quality, 0.0, 1.0)}};
  }
  PoseEstimate Estimate() const override;
  // Matches scans against `map` from now on; the particles stay where they are.
  bool SetMap(const OccupancyGrid& map) override;

  // Scatters particles uniformly over the free space (global localisation, no prior).
  void ScatterUniformly();
  bool GlobalRelocalize() override {
    ScatterUniformly();
    return true;
  }
  // Shares this filter's map model (the likelihood field is not built again).
  std::unique_ptr<Localizer> Fresh() const override;
  size_t particle_count() const;

 private:
  struct Particle {
    Pose2 pose;
    double weight;
  };
  // A pose told ends the nearby reset's watch for a sudden loss; the wake-up's search near where
  // the pose was lost keeps it, so the reset goes on searching for that loss.
  void ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) override;
  void ResetForSearch(const Pose2& pose, const Eigen::Matrix3d& covariance) override;
  // The particles drawn around `pose`, with the mutex held.
  void Reanchor(const Pose2& pose, const Eigen::Matrix3d& covariance);
  bool CanSearch() const override { return true; }
  void MoveParticles(const Pose2& from, const Pose2& to);
  void Resample();
  Pose2 RandomFreePose();
  void UpdateEstimate();
  // Sensor log-likelihood of each particle by the likelihood field, into `sensor`.
  void WeighByLikelihoodField(const std::vector<Point2>& ends, std::vector<double>& sensor) const;
  // Replaces the particles by draws around a whole-map search's candidates, when there are any;
  // with the mutex held.
  void DrawAround(const std::vector<PoseCandidate>& candidates);
  // Replaces a share of the particles by draws around `poses` (shared out among them), before a
  // scan weighs them. With the mutex held.
  void DrawShareAround(const std::vector<Pose2>& poses);
  // The nearby reset: a search of the scan just weighed, started beside the filter when it fits
  // poorly; and, at a later scan (odometry `at_scan`), the pose it found carried on to that scan by
  // the odometry since, and settled on that `scan`. A new pose or a global search leaves a running
  // search be: the pose it finds is where the scans fit, whatever the filter was told meanwhile. A
  // pose found away from the estimate is drawn around once confirmed: by that later scan fitting
  // where it was carried (from the estimate carried to it, `carried`), or failing that by the next
  // search. With the mutex held.
  void StartNearbyReset(const ScanReading& scan);
  bool NearbyResetReady() const;  // a search has ended (or is to be waited for)
  std::vector<Pose2> TakeNearbyReset(const Pose2& at_scan, const Pose2& carried, const ScanReading& scan);
  // Posterior weights from the sensor log-likelihoods (summed over `beams` beams), resampling,
  // estimate; with the mutex held.
  void Reweigh(const std::vector<Point2>& ends, std::vector<double>& sensor, size_t beams);

  ParticleFilterOptions o_;
  // What the filter knows of the map; SetMap replaces it whole.
  struct MapModel {
    MapModel(const OccupancyGrid& grid, const ParticleFilterOptions& o);
    OccupancyGrid map;
    LikelihoodField field;
    std::optional<RayCaster> caster;  // the beam model's ray casts, built only when it is chosen
    std::vector<int32_t> free_cells;
    const GlobalScanSearch& scan_search(const GlobalScanSearchOptions& options) const;  // built on first use

   private:
    mutable std::once_flag scan_search_once;
    mutable std::unique_ptr<GlobalScanSearch> scan_search_;
  };
  std::shared_ptr<const MapModel> model_;  // guarded by mutex_
  ParticleFilterLocalizer(std::shared_ptr<const MapModel> model, const ParticleFilterOptions& options);
  // Sum over `beams` of the beam model's log-likelihood from `pose` (map frame).
  double BeamModelLogLikelihood(const Pose2& pose, const std::vector<ScanBeam>& beams, double range_max) const;

  mutable std::mutex mutex_;
  mutable std::atomic<uint64_t> fresh_filters_{0};  // made by Fresh()
  std::mt19937_64 rng_;
  std::vector<Particle> particles_;
  bool have_odom_ = false;
  Pose2 last_odom_;  // odometry at the last filter update
  Pose2 latest_odom_;
  OdometryHistory odom_history_;  // scans are matched with the particles moved to their own stamp
  bool moved_since_scan_ = true;
  double w_slow_ = 0.0, w_fast_ = 0.0;
  PoseEstimate estimate_;
  struct PendingReset {
    std::future<std::optional<NearbyReset::Found>> found;
    Pose2 odometry;                                 // at the searched scan
    Pose2 estimate;                                 // then
    std::optional<NearbyReset::Expected> expected;  // of the pose awaiting confirmation
    uint64_t poses_set = 0;                         // poses_set_ when it began
  };
  std::optional<PendingReset> nearby_reset_;
  // A pose found farther than relocated_jump from the estimate that the scan after its search did
  // not confirm waits to be found again by the next search where the odometry since puts it: a
  // map that lacks a wall lets a wrong pose fit one scan well, seldom the same wrong pose two scans
  // running. Map frame at the odometry `unconfirmed_at_`.
  std::optional<Pose2> unconfirmed_;
  // The poses the nearby reset last drew around away from the estimate (carried on by the
  // odometry since), for relocated_scans scans after: the estimate that comes to one of them has
  // been relocated.
  std::vector<Pose2> drawn_recently_;
  int scans_since_draw_ = 0;
  Pose2 unconfirmed_at_;
  int unconfirmed_searches_ = 0;                                // searches since that did not find it again
  uint64_t poses_set_ = 0;                                      // times the pose was set or scattered over the map
  int scans_since_good_fit_ = std::numeric_limits<int>::max();  // since the pose was last set
  bool initialised_ = false;
  bool global_mode_ = false;  // relocalising globally: likelihood tempered
  // Scattered for a global relocalisation, no scan searched yet; read outside the lock by AddScan.
  std::atomic<bool> scan_search_due_{false};
};

}  // namespace navd::localization
