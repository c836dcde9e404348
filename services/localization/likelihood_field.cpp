#include "services/localization/likelihood_field.h"

#include "services/common/distance_field.h"

namespace navd::localization {

LikelihoodField::LikelihoodField(const OccupancyGrid& map, const LikelihoodFieldOptions& options)
    : o_(options),
      width_(map.width()),
      height_(map.height()),
      origin_(map.origin()),
      resolution_(map.resolution()),
      inv_resolution_(1.0 / map.resolution()) {
  const DistanceField field(map);
  const double half = resolution_ / 2;
  std::vector<float> surface(field.values().size());  // unpadded
  for (size_t i = 0; i < surface.size(); ++i) {
    const double d = field.values()[i];
    surface[i] = static_cast<float>(d <= 0.0 ? -half : std::min(d - half, o_.max_distance));
  }
  padded_width_ = width_ + 2;
  surface_distance_.resize(static_cast<size_t>(padded_width_) * (height_ + 2));
  for (int y = -1; y <= height_; ++y) {
    for (int x = -1; x <= width_; ++x) {
      const int cx = std::clamp(x, 0, width_ - 1), cy = std::clamp(y, 0, height_ - 1);
      surface_distance_[static_cast<size_t>(y + 1) * padded_width_ + (x + 1)] =
          surface[static_cast<size_t>(cy) * width_ + cx];
    }
  }
  const double rand = o_.z_rand / o_.range_max;
  log_likelihood_table_.resize(static_cast<size_t>(o_.max_distance * 1000) + 2);
  for (size_t mm = 0; mm < log_likelihood_table_.size(); ++mm) {
    const double d = mm / 1000.0;
    log_likelihood_table_[mm] =
        static_cast<float>(std::log(o_.z_hit * std::exp(-d * d / (2 * o_.sigma_hit * o_.sigma_hit)) + rand));
  }
  log_outside_ = static_cast<float>(std::log(rand));
}

const std::vector<float>& LikelihoodField::SignedDistance() const {
  // Built on first use: only the scan-to-map fit needs depths inside obstacles, and a second
  // distance transform at start-up would be wasted on the particle and histogram filters.
  std::call_once(signed_once_, [this] {
    // Inverted: the free side is the "obstacle" whose distance the transform measures.
    OccupancyGrid inverted(width_, height_, resolution_, origin_, OccupancyGrid::kFree);
    signed_distance_.resize(static_cast<size_t>(width_) * height_);
    const float inside = static_cast<float>(-resolution_ / 2);  // the surface field's value in obstacles
    for (int y = 0; y < height_; ++y) {
      for (int x = 0; x < width_; ++x) {
        const float d = surface_distance_[static_cast<size_t>(y + 1) * padded_width_ + (x + 1)];
        signed_distance_[static_cast<size_t>(y) * width_ + x] = d;
        if (d != inside) inverted.set({x, y}, OccupancyGrid::kOccupied);
      }
    }
    const DistanceField depth(inverted);  // from each obstacle cell to the nearest free one
    const double half = resolution_ / 2;
    for (size_t i = 0; i < signed_distance_.size(); ++i) {
      const double d = depth.values()[i];
      if (d > 0.0) signed_distance_[i] = static_cast<float>(-std::min(d - half, o_.max_distance));
    }
  });
  return signed_distance_;
}

bool LikelihoodField::SurfaceDistance(const Point2& p, double* distance, Point2* gradient) const {
  const double gx = (p.x() - origin_.x()) * inv_resolution_ - 0.5;
  const double gy = (p.y() - origin_.y()) * inv_resolution_ - 0.5;
  if (!(gx >= -0.5 && gy >= -0.5 && gx < width_ - 0.5 && gy < height_ - 0.5) || width_ < 2 || height_ < 2) return false;
  const int x0 = std::clamp(static_cast<int>(std::floor(gx)), 0, width_ - 2);
  const int y0 = std::clamp(static_cast<int>(std::floor(gy)), 0, height_ - 2);
  const double fx = std::clamp(gx - x0, 0.0, 1.0), fy = std::clamp(gy - y0, 0.0, 1.0);
  const float* row0 = &SignedDistance()[static_cast<size_t>(y0) * width_ + x0];
  const float* row1 = row0 + width_;
  *distance = (1 - fy) * ((1 - fx) * row0[0] + fx * row0[1]) + fy * ((1 - fx) * row1[0] + fx * row1[1]);
  if (gradient) {
    *gradient = Point2((1 - fy) * (row0[1] - row0[0]) + fy * (row1[1] - row1[0]),
                       (1 - fx) * (row1[0] - row0[0]) + fx * (row1[1] - row0[1])) *
                inv_resolution_;
  }
  return true;
}

double LikelihoodField::Agreement(const Pose2& pose, const std::vector<Point2>& ends) const {
  if (ends.empty()) return 0.0;
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  const float best = log_likelihood_table_[0];
  double sum = 0.0;
  for (const Point2& p : ends) {
    sum += std::exp(
        LogLikelihoodAtCell(ToCellX(pose.x + c * p.x() - s * p.y()), ToCellY(pose.y + s * p.x() + c * p.y())) - best);
  }
  return sum / ends.size();
}

}  // namespace navd::localization
