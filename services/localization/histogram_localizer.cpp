#include "services/localization/histogram_localizer.h"

#include <algorithm>
#include <cmath>

#include "services/common/error.h"
#include "services/localization/scan_points.h"

namespace navd::localization {

namespace {

size_t StatesFor(const OccupancyGrid& map, const HistogramOptions& o) {
  return static_cast<size_t>(std::max(1.0, std::ceil(map.size_x() / o.cell_size))) *
         static_cast<size_t>(std::max(1.0, std::ceil(map.size_y() / o.cell_size))) * o.heading_bins;
}

const HistogramOptions& Checked(const OccupancyGrid& map, const HistogramOptions& o) {
  if (!(o.cell_size > 0.0) || o.heading_bins < 4) {
    throw Error(ErrorCode::kInvalidArgument, "histogram: cell_size must be > 0 and heading_bins >= 4");
  }
  const size_t states = StatesFor(map, o);
  if (states > o.max_states) {
    throw Error(ErrorCode::kInvalidArgument, "histogram: the map needs " + std::to_string(states) +
                                                 " states at cell_size " + std::to_string(o.cell_size) +
                                                 " m (max_states " + std::to_string(o.max_states) +
                                                 "); use a coarser cell or the particle filter");
  }
  return o;
}

}  // namespace

HistogramLocalizer::HistogramLocalizer(const OccupancyGrid& map, const HistogramOptions& options)
    : requested_(Checked(map, options)), o_(requested_) {
  std::lock_guard<std::mutex> lock(mutex_);
  LayOutLocked(map, o_, std::make_unique<const LikelihoodField>(map, o_.field));
}

void HistogramLocalizer::LayOutLocked(const OccupancyGrid& map, const HistogramOptions& o,
                                      std::unique_ptr<const LikelihoodField> field) {
  o_ = o;
  field_ = std::move(field);
  origin_ = map.origin();
  nx_ = std::max(1, static_cast<int>(std::ceil(map.size_x() / o_.cell_size)));
  ny_ = std::max(1, static_cast<int>(std::ceil(map.size_y() / o_.cell_size)));
  nk_ = o_.heading_bins;
  bin_ = 2 * M_PI / nk_;
  const size_t states = StatesFor(map, o_);
  free_.assign(static_cast<size_t>(nx_) * ny_, 0);
  for (int j = 0; j < ny_; ++j) {
    for (int i = 0; i < nx_; ++i) {
      const CellIndex c = map.CellOf(origin_ + Point2((i + 0.5) * o_.cell_size, (j + 0.5) * o_.cell_size));
      free_[static_cast<size_t>(j) * nx_ + i] = map.Contains(c) && OccupancyGrid::IsFreeValue(map.at(c));
    }
  }
  belief_.assign(states, 0.0f);
  scratch_.assign(states, 0.0f);
  GlobalRelocalizeLocked();
}

bool HistogramLocalizer::SetMap(const OccupancyGrid& map) {
  HistogramOptions o = requested_;
  while (StatesFor(map, o) > o.max_states) o.cell_size *= 1.1;
  auto field = std::make_unique<const LikelihoodField>(map, o.field);  // the costly part, outside the lock
  std::lock_guard<std::mutex> lock(mutex_);
  // The belief is at predicted_at_odom_; the reset anchors at the latest odometry (as Estimate()).
  PoseEstimate was = estimate_;
  if (have_odom_) was.pose = was.pose * (predicted_at_odom_.inverse() * odom_history_.latest().pose);
  LayOutLocked(map, o, std::move(field));
  if (have_odom_) ResetPoseLocked(was.pose, was.covariance);
  return true;
}

int HistogramLocalizer::ColumnOf(double x) const {
  return std::clamp(static_cast<int>(std::floor((x - origin_.x()) / o_.cell_size)), 0, nx_ - 1);
}

bool HistogramLocalizer::GlobalRelocalize() {
  std::lock_guard<std::mutex> lock(mutex_);
  GlobalRelocalizeLocked();
  return true;
}

void HistogramLocalizer::GlobalRelocalizeLocked() {
  for (int k = 0; k < nk_; ++k) {
    for (int j = 0; j < ny_; ++j) {
      for (int i = 0; i < nx_; ++i) belief_[Index(i, j, k)] = free_[static_cast<size_t>(j) * nx_ + i] ? 1.0f : 0.0f;
    }
  }
  Normalise();
  if (have_odom_) predicted_at_odom_ = odom_history_.latest().pose;
  moved_since_scan_ = true;
  UpdateEstimateLocked();
}

void HistogramLocalizer::ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  std::lock_guard<std::mutex> lock(mutex_);
  ResetPoseLocked(pose, covariance);
}

void HistogramLocalizer::ResetPoseLocked(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  // A Gaussian over the grid; with no spread given, all mass in the nearest state.
  const double sx = std::sqrt(covariance(0, 0)), sy = std::sqrt(covariance(1, 1)), st = std::sqrt(covariance(2, 2));
  const int ci = ColumnOf(pose.x);
  const int cj = std::clamp(static_cast<int>(std::floor((pose.y - origin_.y()) / o_.cell_size)), 0, ny_ - 1);
  const int ck = static_cast<int>(std::lround((pose.theta + M_PI) / bin_)) % nk_;
  for (int k = 0; k < nk_; ++k) {
    const double dt = NormalizeAngle(HeadingOf(k) - pose.theta);
    for (int j = 0; j < ny_; ++j) {
      const double dy = origin_.y() + (j + 0.5) * o_.cell_size - pose.y;
      for (int i = 0; i < nx_; ++i) {
        const double dx = origin_.x() + (i + 0.5) * o_.cell_size - pose.x;
        double p;
        if (sx > 0 && sy > 0 && st > 0) {
          p = std::exp(-0.5 * (dx * dx / (sx * sx) + dy * dy / (sy * sy) + dt * dt / (st * st)));
        } else {
          p = (i == ci && j == cj && k == ck) ? 1.0 : 0.0;
        }
        belief_[Index(i, j, k)] = static_cast<float>(p);
      }
    }
  }
  Normalise();
  if (have_odom_) predicted_at_odom_ = odom_history_.latest().pose;
  moved_since_scan_ = true;
  UpdateEstimateLocked();
}

void HistogramLocalizer::Normalise() {
  double total = 0.0;
  for (size_t s = 0; s < belief_.size(); ++s) {
    if (!free_[s % free_.size()]) belief_[s] = 0.0f;
    total += belief_[s];
  }
  if (!(total > 0.0)) {  // nothing left anywhere (an impossible observation): start over, uniform
    for (size_t s = 0; s < belief_.size(); ++s) belief_[s] = free_[s % free_.size()] ? 1.0f : 0.0f;
    total = 0.0;
    for (float b : belief_) total += b;
  }
  const float inv = static_cast<float>(1.0 / total);
  for (float& b : belief_) b *= inv;
}

void HistogramLocalizer::Predict(const Pose2& d) {
  // Each state's mass moves by the increment from its own heading, split trilinearly between the
  // states it lands between; mass leaving the grid or landing in obstacles is lost (then renormalised).
  std::fill(scratch_.begin(), scratch_.end(), 0.0f);
  for (int k = 0; k < nk_; ++k) {
    const double th = HeadingOf(k);
    const double c = std::cos(th), s = std::sin(th);
    const double mx = (c * d.x - s * d.y) / o_.cell_size, my = (s * d.x + c * d.y) / o_.cell_size;
    const double fk = k + d.theta / bin_;
    const int k0 = static_cast<int>(std::floor(fk));
    const double wk = fk - k0;
    const int ka = ((k0 % nk_) + nk_) % nk_, kb = (ka + 1) % nk_;
    const int di = static_cast<int>(std::floor(mx)), dj = static_cast<int>(std::floor(my));
    const double wx = mx - di, wy = my - dj;
    const float w[2][2][2] = {
        {{static_cast<float>((1 - wx) * (1 - wy) * (1 - wk)), static_cast<float>(wx * (1 - wy) * (1 - wk))},
         {static_cast<float>((1 - wx) * wy * (1 - wk)), static_cast<float>(wx * wy * (1 - wk))}},
        {{static_cast<float>((1 - wx) * (1 - wy) * wk), static_cast<float>(wx * (1 - wy) * wk)},
         {static_cast<float>((1 - wx) * wy * wk), static_cast<float>(wx * wy * wk)}}};
    for (int j = 0; j < ny_; ++j) {
      for (int i = 0; i < nx_; ++i) {
        const float mass = belief_[Index(i, j, k)];
        if (mass == 0.0f) continue;
        for (int b = 0; b < 2; ++b) {
          const int tj = j + dj + b;
          if (tj < 0 || tj >= ny_) continue;
          for (int a = 0; a < 2; ++a) {
            const int ti = i + di + a;
            if (ti < 0 || ti >= nx_) continue;
            scratch_[Index(ti, tj, ka)] += mass * w[0][b][a];
            scratch_[Index(ti, tj, kb)] += mass * w[1][b][a];
          }
        }
      }
    }
  }
  belief_.swap(scratch_);
}

void HistogramLocalizer::Blur() {
  // The chapter's delta along each axis: p to the intended state, (1 - p) / 2 to each neighbour.
  const float p = static_cast<float>(o_.kernel_centre), q = static_cast<float>((1.0 - o_.kernel_centre) / 2);
  const size_t plane = static_cast<size_t>(nx_) * ny_;
  auto along = [&](size_t count, size_t stride, auto offset_of, bool wrap) {
    std::fill(scratch_.begin(), scratch_.end(), 0.0f);
    for (size_t s = 0; s < belief_.size(); ++s) {
      const float m = belief_[s];
      if (m == 0.0f) continue;
      const size_t pos = offset_of(s);
      scratch_[s] += p * m;
      if (pos > 0)
        scratch_[s - stride] += q * m;
      else if (wrap)
        scratch_[s + (count - 1) * stride] += q * m;
      if (pos + 1 < count)
        scratch_[s + stride] += q * m;
      else if (wrap)
        scratch_[s - (count - 1) * stride] += q * m;
    }
    belief_.swap(scratch_);
  };
  along(
      nx_, 1, [&](size_t s) { return s % nx_; }, false);
  along(
      ny_, nx_, [&](size_t s) { return (s / nx_) % ny_; }, false);
  along(
      nk_, plane, [&](size_t s) { return s / plane; }, true);
}

void HistogramLocalizer::AddOdometry(const OdometryReading& reading) {
  if (!reading.pose.finite()) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!have_odom_) {
    predicted_at_odom_ = reading.pose;
    have_odom_ = true;
  }
  odom_history_.Add(reading);
  // The belief moves in steps of about a cell (or a heading bin), each one action of the chapter's
  // delta, so its spread grows with the motion and not with the odometry's rate.
  const Pose2 d = predicted_at_odom_.inverse() * reading.pose;
  const double steps = std::max(std::hypot(d.x, d.y) / o_.cell_size, std::abs(d.theta) / bin_);
  if (steps < 1.0) return;
  Predict(d);
  for (int n = 0; n < static_cast<int>(steps); ++n) Blur();
  Normalise();
  predicted_at_odom_ = reading.pose;
  moved_since_scan_ = true;
  UpdateEstimateLocked();
}

bool HistogramLocalizer::AddScan(const ScanReading& scan) {
  if (!ScanHeaderIsUsable(scan)) return false;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!have_odom_ || !moved_since_scan_) return false;
  const std::vector<Point2> ends = ScanEndPoints(scan, o_.beams);
  if (ends.size() < 5) return false;
  // Beam ends per heading bin, in the likelihood field's cells. The scan is taken at the cell
  // centres of the belief as it stands (moved to within a cell of the scan's time).
  const size_t nb = ends.size();
  std::vector<float> ex(nb * nk_), ey(nb * nk_);
  for (int k = 0; k < nk_; ++k) {
    const double c = std::cos(HeadingOf(k)), s = std::sin(HeadingOf(k));
    for (size_t b = 0; b < nb; ++b) {
      ex[k * nb + b] = static_cast<float>((c * ends[b].x() - s * ends[b].y()) * field_->inv_resolution());
      ey[k * nb + b] = static_cast<float>((s * ends[b].x() + c * ends[b].y()) * field_->inv_resolution());
    }
  }
  std::vector<float>& log_weight = scratch_;
  float best = -std::numeric_limits<float>::infinity();
  for (int k = 0; k < nk_; ++k) {
    for (int j = 0; j < ny_; ++j) {
      const float cy = field_->ToCellY(origin_.y() + (j + 0.5) * o_.cell_size);
      for (int i = 0; i < nx_; ++i) {
        const size_t s = Index(i, j, k);
        if (belief_[s] <= 0.0f) continue;
        const float cx = field_->ToCellX(origin_.x() + (i + 0.5) * o_.cell_size);
        float sum = 0.0f;
        for (size_t b = 0; b < nb; ++b) sum += field_->LogLikelihoodAtCell(cx + ex[k * nb + b], cy + ey[k * nb + b]);
        log_weight[s] = static_cast<float>(o_.likelihood_scale) * sum + std::log(belief_[s]);
        best = std::max(best, log_weight[s]);
      }
    }
  }
  const float prune = static_cast<float>(std::log(o_.prune_below));
  for (size_t s = 0; s < belief_.size(); ++s) {
    if (belief_[s] > 0.0f) belief_[s] = log_weight[s] - best < prune ? 0.0f : std::exp(log_weight[s] - best);
  }
  Normalise();
  moved_since_scan_ = false;
  UpdateEstimateLocked();
  estimate_.quality = field_->Agreement(estimate_.pose, ends);
  return true;
}

void HistogramLocalizer::UpdateEstimateLocked() {
  const size_t best = std::max_element(belief_.begin(), belief_.end()) - belief_.begin();
  const int bi = static_cast<int>(best % nx_), bj = static_cast<int>((best / nx_) % ny_),
            bk = static_cast<int>(best / (static_cast<size_t>(nx_) * ny_));
  // The mean of the mode's neighbourhood: a fraction of a cell, not the cell's centre.
  double w = 0, x = 0, y = 0, c = 0, s = 0;
  for (int k = bk - 1; k <= bk + 1; ++k) {
    const int kk = (k + nk_) % nk_;
    for (int j = std::max(0, bj - 1); j <= std::min(ny_ - 1, bj + 1); ++j) {
      for (int i = std::max(0, bi - 1); i <= std::min(nx_ - 1, bi + 1); ++i) {
        const double m = belief_[Index(i, j, kk)];
        w += m;
        x += m * (origin_.x() + (i + 0.5) * o_.cell_size);
        y += m * (origin_.y() + (j + 0.5) * o_.cell_size);
        c += m * std::cos(HeadingOf(kk));
        s += m * std::sin(HeadingOf(kk));
      }
    }
  }
  if (w > 0) estimate_.pose = {x / w, y / w, std::atan2(s, c)};
  // Spread of the whole belief around it: large when other hypotheses hold mass.
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int k = 0; k < nk_; ++k) {
    const double dt = NormalizeAngle(HeadingOf(k) - estimate_.pose.theta);
    for (int j = 0; j < ny_; ++j) {
      const double dy = origin_.y() + (j + 0.5) * o_.cell_size - estimate_.pose.y;
      for (int i = 0; i < nx_; ++i) {
        const double m = belief_[Index(i, j, k)];
        if (m == 0.0) continue;
        const Eigen::Vector3d d(origin_.x() + (i + 0.5) * o_.cell_size - estimate_.pose.x, dy, dt);
        cov += m * d * d.transpose();
      }
    }
  }
  const double q = o_.cell_size * o_.cell_size / 12;  // quantisation
  cov.diagonal() += Eigen::Vector3d(q, q, bin_ * bin_ / 12);
  estimate_.covariance = cov;
  estimate_.valid = have_odom_;
}

PoseEstimate HistogramLocalizer::Estimate() const {
  std::lock_guard<std::mutex> lock(mutex_);
  PoseEstimate e = estimate_;
  e.valid = have_odom_;
  if (have_odom_) {
    e.stamp = odom_history_.latest().stamp;
    e.pose = e.pose * (predicted_at_odom_.inverse() * odom_history_.latest().pose);
  }
  return e;
}

MethodContext HistogramLocalizer::Suitability(bool laser_fresh) const {
  return {name(), laser_fresh ? 1.0 : 0.0, {1.0, 4.0, 1.0 + 4.0 * std::clamp(Estimate().quality, 0.0, 1.0)}};
}

std::vector<double> HistogramLocalizer::MarginalX() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<double> m(nx_, 0.0);
  for (size_t s = 0; s < belief_.size(); ++s) m[s % nx_] += belief_[s];
  return m;
}

}  // namespace navd::localization
