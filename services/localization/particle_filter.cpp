#include "services/localization/particle_filter.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <unordered_set>

#include "services/common/ziggurat_normal.h"
#include "services/localization/scan_points.h"

namespace navd::localization {

namespace {
// The motion model's noise grows with the square of each step, so a move cut into k steps spreads
// the cloud sqrt(k) times less than the same move made at once: scans move the particles by the
// whole motion since the last update (as AMCL's update does), and only without scans for a metre
// or a radian (at the default thresholds) does the cloud follow the odometry on its own. A laser
// that scans every 0.5-1 m of travel (as the real logs do) needs a cloud spread by the whole step.
constexpr double kScanlessSteps = 20.0;  // x the update thresholds
}  // namespace

ParticleFilterLocalizer::MapModel::MapModel(const OccupancyGrid& grid, const ParticleFilterOptions& o)
    : map(grid), field(grid, {o.sigma_hit, o.z_hit, o.z_rand, o.max_distance, o.range_max}) {
  if (o.sensor_model == SensorModel::kBeam) caster.emplace(grid);
  for (size_t i = 0; i < map.cells().size(); ++i)
    if (OccupancyGrid::IsFreeValue(map.cells()[i])) free_cells.push_back(static_cast<int32_t>(i));
}

const GlobalScanSearch& ParticleFilterLocalizer::MapModel::scan_search(const GlobalScanSearchOptions& options) const {
  std::call_once(scan_search_once, [&] { scan_search_ = std::make_unique<GlobalScanSearch>(map, field, options); });
  return *scan_search_;
}

ParticleFilterLocalizer::ParticleFilterLocalizer(const OccupancyGrid& map, const ParticleFilterOptions& options)
    : ParticleFilterLocalizer(std::make_shared<const MapModel>(map, options), options) {}

ParticleFilterLocalizer::ParticleFilterLocalizer(std::shared_ptr<const MapModel> model,
                                                 const ParticleFilterOptions& options)
    : o_(options), model_(std::move(model)), rng_(options.seed) {}

std::unique_ptr<Localizer> ParticleFilterLocalizer::Fresh() const {
  std::shared_ptr<const MapModel> model;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    model = model_;
  }
  ParticleFilterOptions o = o_;
  o.seed += ++fresh_filters_;  // another draw than this filter's, and than the last search's
  return std::unique_ptr<Localizer>(new ParticleFilterLocalizer(std::move(model), o));
}

bool ParticleFilterLocalizer::SetMap(const OccupancyGrid& map) {
  auto model = std::make_shared<const MapModel>(map, o_);  // the costly part, outside the lock
  std::lock_guard<std::mutex> lock(mutex_);
  model_ = std::move(model);
  return true;
}

size_t ParticleFilterLocalizer::particle_count() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return particles_.size();
}

Pose2 ParticleFilterLocalizer::RandomFreePose() {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  if (model_->free_cells.empty()) return {};
  const int32_t i =
      model_->free_cells[static_cast<size_t>(u(rng_) * model_->free_cells.size()) % model_->free_cells.size()];
  const Point2 c = model_->map.CellCenter({i % model_->map.width(), i / model_->map.width()});
  const double r = model_->map.resolution();
  return {c.x() + (u(rng_) - 0.5) * r, c.y() + (u(rng_) - 0.5) * r, NormalizeAngle(u(rng_) * 2 * M_PI)};
}

void ParticleFilterLocalizer::ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  std::lock_guard<std::mutex> lock(mutex_);
  Reanchor(pose, covariance);
  scans_since_good_fit_ = std::numeric_limits<int>::max();
  unconfirmed_.reset();
  drawn_recently_.clear();
  ++poses_set_;
}

void ParticleFilterLocalizer::ResetForSearch(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  std::lock_guard<std::mutex> lock(mutex_);
  Reanchor(pose, covariance);
}

void ParticleFilterLocalizer::Reanchor(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  const double sx = covariance(0, 0) > 0 ? std::sqrt(covariance(0, 0)) : o_.initial_sigma_xy;
  const double sy = covariance(1, 1) > 0 ? std::sqrt(covariance(1, 1)) : o_.initial_sigma_xy;
  const double st = covariance(2, 2) > 0 ? std::sqrt(covariance(2, 2)) : o_.initial_sigma_theta;
  const ZigguratNormal n;
  const int count = std::clamp(2 * o_.min_particles, o_.min_particles, o_.max_particles);
  particles_.assign(count, {});
  for (auto& p : particles_) {
    p.pose = {pose.x + sx * n(rng_), pose.y + sy * n(rng_), NormalizeAngle(pose.theta + st * n(rng_))};
    p.weight = 1.0 / count;
  }
  last_odom_ = latest_odom_;
  moved_since_scan_ = true;
  w_slow_ = w_fast_ = 0.0;
  initialised_ = true;
  global_mode_ = false;
  scan_search_due_ = false;
  UpdateEstimate();
}

void ParticleFilterLocalizer::DrawAround(const std::vector<PoseCandidate>& candidates) {
  scan_search_due_ = false;
  double total = 0.0;
  for (const PoseCandidate& c : candidates) total += c.score;
  if (!(total > 0.0)) return;  // nothing fits anywhere: the uniform particles stay
  const ZigguratNormal n;
  std::vector<Particle> drawn;
  drawn.reserve(o_.max_particles);
  for (const PoseCandidate& c : candidates) {
    const int count = std::max(1, static_cast<int>(std::lround(o_.max_particles * c.score / total)));
    for (int i = 0; i < count; ++i) {
      drawn.push_back({{c.pose.x + o_.scan_search_sigma_xy * n(rng_), c.pose.y + o_.scan_search_sigma_xy * n(rng_),
                        NormalizeAngle(c.pose.theta + o_.scan_search_sigma_theta * n(rng_))},
                       0.0});
    }
  }
  for (auto& p : drawn) p.weight = 1.0 / drawn.size();
  particles_.swap(drawn);
}

void ParticleFilterLocalizer::ScatterUniformly() {
  std::lock_guard<std::mutex> lock(mutex_);
  particles_.assign(o_.global_particles, {});
  for (auto& p : particles_) p = {RandomFreePose(), 1.0 / o_.global_particles};
  global_mode_ = true;
  scan_search_due_ = o_.scan_search;
  scans_since_good_fit_ = std::numeric_limits<int>::max();
  unconfirmed_.reset();
  drawn_recently_.clear();
  ++poses_set_;
  last_odom_ = latest_odom_;
  moved_since_scan_ = true;
  w_slow_ = w_fast_ = 0.0;
  initialised_ = true;
  UpdateEstimate();
}

void ParticleFilterLocalizer::AddOdometry(const OdometryReading& reading) {
  if (!reading.pose.finite()) return;  // never let a NaN into the particles
  std::lock_guard<std::mutex> lock(mutex_);
  if (!have_odom_) {
    last_odom_ = latest_odom_ = reading.pose;
    have_odom_ = true;
  }
  latest_odom_ = reading.pose;
  estimate_.stamp = reading.stamp;
  odom_history_.Add(reading);
  const Pose2 delta = last_odom_.inverse() * latest_odom_;
  const double moved = std::hypot(delta.x, delta.y), turned = std::abs(delta.theta);
  if (moved >= o_.update_min_distance || turned >= o_.update_min_angle) moved_since_scan_ = true;
  // Scans move the particles (to their own stamp); without scans the cloud still follows the
  // odometry, and spreads, in coarser steps.
  if (moved >= kScanlessSteps * o_.update_min_distance || turned >= kScanlessSteps * o_.update_min_angle) {
    if (initialised_) MoveParticles(last_odom_, latest_odom_);
    last_odom_ = latest_odom_;
    if (initialised_) UpdateEstimate();
  }
}

void ParticleFilterLocalizer::MoveParticles(const Pose2& from, const Pose2& to) {
  const double dx = to.x - from.x, dy = to.y - from.y;
  const double trans = std::hypot(dx, dy);
  const ZigguratNormal n;
  if (o_.motion_model == MotionModel::kOmni) {
    // Translate along the motion's bearing in the robot frame, slip across it, rotate; each
    // particle carries the same body-frame motion from its own heading.
    const double rot = NormalizeAngle(to.theta - from.theta);
    const double bearing = trans < 1e-9 ? 0.0 : NormalizeAngle(std::atan2(dy, dx) - from.theta);
    const double s_trans = std::sqrt(o_.alpha3 * trans * trans + o_.alpha1 * rot * rot);
    const double s_rot = std::sqrt(o_.alpha4 * rot * rot + o_.alpha2 * trans * trans);
    const double s_strafe = std::sqrt(o_.alpha1 * rot * rot + o_.alpha5 * trans * trans);
    for (auto& p : particles_) {
      const double t = trans + s_trans * n(rng_);
      const double side = s_strafe * n(rng_);
      const double heading = p.pose.theta + bearing;
      p.pose.x += t * std::cos(heading) - side * std::sin(heading);
      p.pose.y += t * std::sin(heading) + side * std::cos(heading);
      p.pose.theta = NormalizeAngle(p.pose.theta + rot + s_rot * n(rng_));
    }
    return;
  }
  // sample_motion_model_odometry: rotate, translate, rotate, each with noise.
  // Backwards motion is a translation with the robot's heading, not a half turn.
  double rot1 = trans < 0.01 ? 0.0 : NormalizeAngle(std::atan2(dy, dx) - from.theta);
  double signed_trans = trans;
  if (std::abs(rot1) > M_PI / 2) {
    rot1 = NormalizeAngle(rot1 + M_PI);
    signed_trans = -trans;
  }
  const double rot2 = NormalizeAngle(to.theta - from.theta - rot1);
  const double s_rot1 = std::sqrt(o_.alpha1 * rot1 * rot1 + o_.alpha2 * trans * trans);
  const double s_trans = std::sqrt(o_.alpha3 * trans * trans + o_.alpha4 * (rot1 * rot1 + rot2 * rot2));
  const double s_rot2 = std::sqrt(o_.alpha1 * rot2 * rot2 + o_.alpha2 * trans * trans);
  for (auto& p : particles_) {
    const double r1 = rot1 + s_rot1 * n(rng_);
    const double t = signed_trans + s_trans * n(rng_);
    const double r2 = rot2 + s_rot2 * n(rng_);
    p.pose.x += t * std::cos(p.pose.theta + r1);
    p.pose.y += t * std::sin(p.pose.theta + r1);
    p.pose.theta = NormalizeAngle(p.pose.theta + r1 + r2);
  }
}

bool ParticleFilterLocalizer::AddScan(const ScanReading& scan) {
  if (!ScanHeaderIsUsable(scan)) return false;
  // The whole-map search takes a tenth of a second or more: outside the lock, so the estimate
  // stays readable meanwhile; its candidates count only if the map is still the one searched.
  std::optional<std::vector<PoseCandidate>> candidates;
  std::shared_ptr<const MapModel> searched;
  if (scan_search_due_) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      searched = model_;
    }
    candidates = searched->scan_search(o_.scan_search_options).Search(ScanEndPoints(scan, 0));
  }
  std::lock_guard<std::mutex> lock(mutex_);
  // A robot standing still adds nothing new with each scan, unless the nearby reset has a pose to
  // try: a robot set down and left standing must still be found.
  if (!initialised_ || !have_odom_ || (!moved_since_scan_ && !NearbyResetReady())) return false;
  const Pose2 at_scan = odom_history_.At(scan.stamp);
  const Pose2 carried = estimate_.pose * (last_odom_.inverse() * at_scan);  // by the odometry alone
  for (Pose2& pose : drawn_recently_) pose = pose * (last_odom_.inverse() * at_scan);
  MoveParticles(last_odom_, at_scan);
  last_odom_ = at_scan;
  if (candidates && scan_search_due_ && searched == model_) DrawAround(*candidates);
  const NearbyReset reset(o_.nearby_reset);
  const std::vector<Pose2> drawn = TakeNearbyReset(at_scan, carried, scan);
  DrawShareAround(drawn);
  if (!drawn.empty()) {
    // Only draws away from the estimate relocate it.
    drawn_recently_.clear();
    for (const Pose2& pose : drawn)
      if (!reset.Near(pose, carried)) drawn_recently_.push_back(pose);
    scans_since_draw_ = 0;
  } else if (++scans_since_draw_ >= o_.nearby_reset.relocated_scans) {
    drawn_recently_.clear();
  }
  const std::vector<Point2> ends = ScanEndPoints(scan, o_.beams);
  if (ends.size() < 5) return false;  // too little to judge by
  std::vector<double> sensor(particles_.size());
  size_t beam_count = ends.size();
  if (o_.sensor_model == SensorModel::kBeam) {
    const std::vector<ScanBeam> beams = SampleBeams(scan, o_.beam_model.beams);
    for (size_t k = 0; k < particles_.size(); ++k) {
      sensor[k] = BeamModelLogLikelihood(particles_[k].pose, beams, scan.range_max);
    }
    beam_count = beams.size();
  } else {
    WeighByLikelihoodField(ends, sensor);
  }
  Reweigh(ends, sensor, beam_count);
  // Relocated: the estimate has come to a pose drawn away from it.
  if (std::any_of(drawn_recently_.begin(), drawn_recently_.end(),
                  [&](const Pose2& pose) { return reset.Near(pose, estimate_.pose); })) {
    ++estimate_.relocations;
    drawn_recently_.clear();
  }
  StartNearbyReset(scan);
  return true;
}

void ParticleFilterLocalizer::StartNearbyReset(const ScanReading& scan) {
  if (!(estimate_.quality < o_.nearby_reset.below_quality)) unconfirmed_.reset();  // fits again as it is
  if (estimate_.quality >= o_.nearby_reset.good_quality) {
    scans_since_good_fit_ = 0;
  } else if (scans_since_good_fit_ < std::numeric_limits<int>::max()) {
    ++scans_since_good_fit_;
  }
  if (scans_since_good_fit_ > o_.nearby_reset.within_scans) return;
  if (global_mode_ || !o_.nearby_reset.enabled || nearby_reset_ || !(estimate_.quality < o_.nearby_reset.below_quality))
    return;
  std::optional<NearbyReset::Expected> expected;
  if (unconfirmed_) expected = NearbyReset(o_.nearby_reset).Expect(*unconfirmed_, unconfirmed_at_, last_odom_);
  // The search holds the map model it searches, whatever SetMap does meanwhile.
  nearby_reset_ = PendingReset{std::async(std::launch::async,
                                          [model = model_, options = o_, estimate = estimate_.pose,
                                           quality = estimate_.quality, points = ScanEndPoints(scan, 0), expected] {
                                            return NearbyReset(options.nearby_reset)
                                                .Check(model->scan_search(options.scan_search_options), estimate,
                                                       quality, points, expected ? &*expected : nullptr);
                                          }),
                               last_odom_, estimate_.pose, expected, poses_set_};
}

bool ParticleFilterLocalizer::NearbyResetReady() const {
  return nearby_reset_ && (o_.nearby_reset.wait_for_search ||
                           nearby_reset_->found.wait_for(std::chrono::seconds(0)) == std::future_status::ready);
}

std::vector<Pose2> ParticleFilterLocalizer::TakeNearbyReset(const Pose2& at_scan, const Pose2& carried,
                                                            const ScanReading& scan) {
  if (!NearbyResetReady()) return {};
  const std::optional<NearbyReset::Found> found = nearby_reset_->found.get();
  const Pose2 odometry = nearby_reset_->odometry, estimate = nearby_reset_->estimate;
  const std::optional<NearbyReset::Expected> expected = nearby_reset_->expected;
  const bool stale = nearby_reset_->poses_set != poses_set_;
  nearby_reset_.reset();
  // Begun before the pose was set or scattered, or for a pose forgotten since (a good fit again).
  if (stale || (expected && !unconfirmed_)) return {};
  if (!found) {
    // A pose awaiting confirmation that a search did not find is looked for again, a few times.
    if (unconfirmed_ && ++unconfirmed_searches_ >= o_.nearby_reset.confirm_searches) unconfirmed_.reset();
    return {};
  }
  const NearbyReset reset(o_.nearby_reset);
  const GlobalScanSearch& search = model_->scan_search(o_.scan_search_options);
  const std::vector<Point2> points = ScanEndPoints(scan, 0);
  const Pose2& pose = found->best.pose;
  const Pose2 here = pose * (odometry.inverse() * at_scan);
  if (expected && reset.Confirms(*expected, pose)) {
    unconfirmed_.reset();
    return {reset.Settle(search, here, points)};
  }
  if (!expected && Distance(pose.translation(), estimate.translation()) <= o_.nearby_reset.relocated_jump)
    return {reset.Settle(search, here, points)};
  // A pose found elsewhere: this scan confirms it where the odometry has carried it, or it awaits
  // the next search's confirmation.
  std::vector<Pose2> confirmed = reset.ConfirmWhereCarried(search, *found, odometry, at_scan, carried, points);
  if (!confirmed.empty()) {
    unconfirmed_.reset();
    for (Pose2& p : confirmed) p = reset.Settle(search, p, points);
    return confirmed;
  }
  unconfirmed_ = pose;
  unconfirmed_at_ = odometry;
  unconfirmed_searches_ = 0;
  return {};
}

void ParticleFilterLocalizer::DrawShareAround(const std::vector<Pose2>& poses) {
  const NearbyResetOptions& r = o_.nearby_reset;
  const size_t count = static_cast<size_t>(std::lround(r.share * particles_.size()));
  if (count == 0 || poses.empty()) return;
  const ZigguratNormal n;
  // Every k-th particle, so the cloud keeps its shape, the poses in turn; each drawn one gets the
  // mean weight.
  const size_t every = std::max<size_t>(1, particles_.size() / count);
  const double weight = 1.0 / particles_.size();
  for (size_t k = 0, i = 0; k < particles_.size(); k += every, ++i) {
    const Pose2& pose = poses[i % poses.size()];
    particles_[k] = {{pose.x + r.sigma_xy * n(rng_), pose.y + r.sigma_xy * n(rng_),
                      NormalizeAngle(pose.theta + r.sigma_theta * n(rng_))},
                     weight};
  }
  double total = 0.0;
  for (const auto& p : particles_) total += p.weight;
  for (auto& p : particles_) p.weight /= total;
}

void ParticleFilterLocalizer::WeighByLikelihoodField(const std::vector<Point2>& ends,
                                                     std::vector<double>& sensor) const {
  // Sensor log-likelihood of each particle, summed over the beams; in float cells of the map
  // (shifted by half a cell) from here on, since this loop runs particles x beams times.
  std::vector<float> end_x(ends.size()), end_y(ends.size());
  for (size_t j = 0; j < ends.size(); ++j) {
    end_x[j] = static_cast<float>(ends[j].x() * model_->field.inv_resolution());
    end_y[j] = static_cast<float>(ends[j].y() * model_->field.inv_resolution());
  }
  for (size_t k = 0; k < particles_.size(); ++k) {
    const Pose2& p = particles_[k].pose;
    const float c = static_cast<float>(std::cos(p.theta)), s = static_cast<float>(std::sin(p.theta));
    const float px = model_->field.ToCellX(p.x), py = model_->field.ToCellY(p.y);
    float sum = 0.0f;
    for (size_t j = 0; j < end_x.size(); ++j) {
      sum += model_->field.LogLikelihoodAtCell(px + c * end_x[j] - s * end_y[j], py + s * end_x[j] + c * end_y[j]);
    }
    sensor[k] = sum;
  }
}

double ParticleFilterLocalizer::BeamModelLogLikelihood(const Pose2& pose, const std::vector<ScanBeam>& beams,
                                                       double range_max) const {
  const BeamModelOptions& b = o_.beam_model;
  const double norm = 1.0 / (b.sigma_hit * std::sqrt(2 * M_PI));
  double sum = 0.0;
  for (const ScanBeam& beam : beams) {
    const double expected =
        std::min(model_->caster->CastOpenEdge(pose.translation(), pose.theta + beam.angle, range_max), range_max);
    const double z = beam.range;
    double p = b.z_rand / range_max;
    if (!beam.hit) {
      p += b.z_max;  // a no-return: the max-range spike
    } else {
      const double d = z - expected;
      p += b.z_hit * norm * std::exp(-0.5 * d * d / (b.sigma_hit * b.sigma_hit));
      if (z < expected)
        p += b.z_short * b.lambda_short * std::exp(-b.lambda_short * z) / (1.0 - std::exp(-b.lambda_short * expected));
    }
    sum += std::log(p);
  }
  return sum;
}

void ParticleFilterLocalizer::Reweigh(const std::vector<Point2>& ends, std::vector<double>& sensor, size_t beams) {
  // The belief's expected per-beam log-likelihood: how well the scan fits where the filter thinks
  // the robot is. Augmented MCL tracks it on two time scales.
  double expected = 0.0;
  for (size_t k = 0; k < particles_.size(); ++k) expected += particles_[k].weight * sensor[k];
  const double beam_log_likelihood = expected / static_cast<double>(std::max<size_t>(1, beams));
  const double w_avg = std::exp(beam_log_likelihood);
  if (w_slow_ == 0.0) w_slow_ = w_fast_ = w_avg;
  w_slow_ += o_.alpha_slow * (w_avg - w_slow_);
  w_fast_ += o_.alpha_fast * (w_avg - w_fast_);

  // Posterior weights, normalised in log space. During global relocalisation, until the belief
  // has gathered (spread under tempering_spread), the likelihood is tempered: beams are far from
  // independent, and at full strength one scan collapses the set onto whichever hypothesis fits
  // best by chance, before the robot has seen enough to tell look-alike places apart. Tracking is
  // never tempered (a spread cloud after a long odometry step, or after random injection, must
  // still be pulled together by the scan).
  const double spread = estimate_.PositionSpread();
  if (global_mode_ && spread < o_.tempering_spread) global_mode_ = false;
  const double temper = global_mode_ ? o_.tempering : 1.0;
  double best = -std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < particles_.size(); ++k) {
    sensor[k] = temper * sensor[k] + std::log(std::max(particles_[k].weight, 1e-300));
    best = std::max(best, sensor[k]);
  }
  double total = 0.0;
  for (size_t k = 0; k < particles_.size(); ++k) total += (particles_[k].weight = std::exp(sensor[k] - best));
  double sum_sq = 0.0;
  for (auto& p : particles_) {
    p.weight /= total;
    sum_sq += p.weight * p.weight;
  }
  const double effective = 1.0 / sum_sq;
  const double inject = std::max(0.0, 1.0 - w_fast_ / w_slow_);
  if (effective < particles_.size() / 2.0 || inject > 0.0) Resample();
  moved_since_scan_ = false;
  UpdateEstimate();
  estimate_.quality = model_->field.Agreement(estimate_.pose, ends);
}

void ParticleFilterLocalizer::Resample() {
  // KLD-sampling (Fox 2003): draw until the particle count bounds the KL error of the belief's
  // histogram, given the number of histogram bins the draws have hit so far.
  const double inject = std::max(0.0, 1.0 - w_fast_ / w_slow_);
  std::vector<double> cdf(particles_.size());
  double acc = 0.0;
  for (size_t k = 0; k < particles_.size(); ++k) cdf[k] = (acc += particles_[k].weight);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Particle> next;
  next.reserve(o_.max_particles);
  std::unordered_set<int64_t> bins;
  size_t target = o_.min_particles;
  while (next.size() < static_cast<size_t>(o_.max_particles) && next.size() < target) {
    Pose2 pose;
    if (u(rng_) < inject) {
      pose = RandomFreePose();
    } else {
      const size_t k = std::lower_bound(cdf.begin(), cdf.end(), u(rng_) * acc) - cdf.begin();
      pose = particles_[std::min(k, particles_.size() - 1)].pose;
    }
    next.push_back({pose, 0.0});
    const int64_t bx = static_cast<int64_t>(std::floor(pose.x / o_.kld_bin_xy));
    const int64_t by = static_cast<int64_t>(std::floor(pose.y / o_.kld_bin_xy));
    const int64_t bt = static_cast<int64_t>(std::floor((pose.theta + M_PI) / o_.kld_bin_theta));
    if (bins.insert((bx * 73856093) ^ (by * 19349663) ^ (bt * 83492791)).second && bins.size() > 1) {
      const double k = static_cast<double>(bins.size() - 1);
      const double a = 2.0 / (9.0 * k);
      const double n = k / (2.0 * o_.kld_error) * std::pow(1.0 - a + std::sqrt(a) * o_.kld_z, 3);
      target = std::max<size_t>(o_.min_particles, static_cast<size_t>(std::ceil(n)));
    }
  }
  for (auto& p : next) p.weight = 1.0 / next.size();
  particles_.swap(next);
  if (inject > 0.0) w_slow_ = w_fast_ = 0.5 * (w_slow_ + w_fast_);  // do not keep injecting on stale averages
}

void ParticleFilterLocalizer::UpdateEstimate() {
  double x = 0, y = 0, c = 0, s = 0;
  for (const auto& p : particles_) {
    x += p.weight * p.pose.x;
    y += p.weight * p.pose.y;
    c += p.weight * std::cos(p.pose.theta);
    s += p.weight * std::sin(p.pose.theta);
  }
  const Pose2 mean{x, y, std::atan2(s, c)};
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : particles_) {
    const Eigen::Vector3d d(p.pose.x - mean.x, p.pose.y - mean.y, NormalizeAngle(p.pose.theta - mean.theta));
    cov += p.weight * d * d.transpose();
  }
  estimate_.pose = mean;
  estimate_.covariance = cov;
  estimate_.valid = initialised_ && have_odom_;
}

PoseEstimate ParticleFilterLocalizer::Estimate() const {
  std::lock_guard<std::mutex> lock(mutex_);
  PoseEstimate e = estimate_;
  e.valid = initialised_ && have_odom_;
  // Between filter updates, carry the estimate along with the odometry since the last one.
  e.pose = e.pose * (last_odom_.inverse() * latest_odom_);
  return e;
}

}  // namespace navd::localization
