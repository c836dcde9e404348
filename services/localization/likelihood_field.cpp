#include "services/localization/likelihood_field.h"

#include <algorithm>
#include <cmath>

#include "services/common/distance_field.h"

namespace navd::localization {

LikelihoodField::LikelihoodField(const OccupancyGrid& map, const LikelihoodFieldOptions& options)
    : o_(options),
      width_(map.width()),
      height_(map.height()),
      origin_(map.origin()),
      resolution_(map.resolution()),
      inv_resolution_(1.0 / map.resolution()) {
  const DistanceField to_occupied(map, DistanceTo::kOccupied);
  const DistanceField to_free(map, DistanceTo::kFree);
  const DistanceField to_open(map, DistanceTo::kNotOccupied);
  // Centre-to-centre distances, less these, are distances to the surface from either side.
  const double before = (0.5 - o_.surface_in_cell) * resolution_, behind = (0.5 + o_.surface_in_cell) * resolution_;
  // A map with no free cell has no free side to be behind: its unknown cells read as free ones.
  const bool has_free = !to_free.values().empty() && std::isfinite(to_free.values().front());
  std::vector<float> field(to_occupied.values().size());  // unpadded
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const size_t i = static_cast<size_t>(y) * width_ + x;
      const int8_t value = map.at({x, y});
      double d = to_occupied.values()[i] - before;
      if (value >= OccupancyGrid::kOccupiedThreshold)
        d = -(to_open.values()[i] - behind);
      else if (!OccupancyGrid::IsFreeValue(value) && has_free)
        d = std::max(d, to_free.values()[i] - behind);
      field[i] = static_cast<float>(std::clamp(d, -o_.max_distance, o_.max_distance));
    }
  }
  padded_width_ = width_ + 2;
  surface_distance_.resize(static_cast<size_t>(padded_width_) * (height_ + 2));
  for (int y = -1; y <= height_; ++y) {
    for (int x = -1; x <= width_; ++x) {
      const int cx = std::clamp(x, 0, width_ - 1), cy = std::clamp(y, 0, height_ - 1);
      surface_distance_[static_cast<size_t>(y + 1) * padded_width_ + (x + 1)] =
          field[static_cast<size_t>(cy) * width_ + cx];
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

bool LikelihoodField::SurfaceDistance(const Point2& p, double* distance, Point2* gradient) const {
  const double gx = (p.x() - origin_.x()) * inv_resolution_ - 0.5;
  const double gy = (p.y() - origin_.y()) * inv_resolution_ - 0.5;
  if (!(gx >= -0.5 && gy >= -0.5 && gx < width_ - 0.5 && gy < height_ - 0.5) || width_ < 2 || height_ < 2) return false;
  const int x0 = std::clamp(static_cast<int>(std::floor(gx)), 0, width_ - 2);
  const int y0 = std::clamp(static_cast<int>(std::floor(gy)), 0, height_ - 2);
  const double fx = std::clamp(gx - x0, 0.0, 1.0), fy = std::clamp(gy - y0, 0.0, 1.0);
  const float* row0 = &surface_distance_[static_cast<size_t>(y0 + 1) * padded_width_ + (x0 + 1)];
  const float* row1 = row0 + padded_width_;
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
