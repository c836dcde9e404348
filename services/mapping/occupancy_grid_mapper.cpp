#include "services/mapping/occupancy_grid_mapper.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "services/common/error.h"
#include "services/common/grid_traversal.h"
#include "services/common/scan_reach.h"

namespace navd::mapping {

double ResolutionToFit(const Point2& min, const Point2& max, double resolution) {
  const double w = max.x() - min.x(), h = max.y() - min.y();
  const double most = static_cast<double>(OccupancyGrid::kMaxCells);
  const auto cells = [&](double r) { return std::ceil(w / r) * std::ceil(h / r); };
  // An extent that is not a positive, finite area is left to the mapper to refuse.
  if (!(w > 0.0) || !(h > 0.0) || !std::isfinite(w) || !std::isfinite(h) || cells(resolution) <= most)
    return resolution;
  // At least the square's size and, for a thin extent (one row of cells), its length over the
  // limit; then up in 5 mm steps, which the ceilings need only a few of. Past kMaxFitted the
  // extent is no map (a corrupt pose), and the mapper refuses it at the resolution asked for.
  constexpr double kStep = 0.005, kMaxFitted = 1.0;
  const double least = std::max({std::sqrt(w * h / most), w / most, h / most});
  for (long k = static_cast<long>(std::ceil(least / kStep)); k * kStep <= kMaxFitted; ++k)
    if (cells(k * kStep) <= most) return std::max(k * kStep, resolution);
  return resolution;
}

double ScanReachOf(const MapperOptions& o, const std::vector<float>& ranges, double range_max) {
  return ScanReach(ranges, std::min(o.max_range, range_max), {o.usable_range, o.far_usable_range, o.min_near_echoes});
}

double TracedLength(const MapperOptions& o, double range, double range_max, double reach) {
  const bool no_return = range >= std::min(o.max_range, range_max);
  return std::min(no_return ? o.missing_data_ray_length : range, reach);
}

OccupancyGridMapper::OccupancyGridMapper(const Point2& min, const Point2& max, const MapperOptions& options)
    : o_(options) {
  const long long w = static_cast<long long>(std::ceil((max.x() - min.x()) / options.resolution));
  const long long h = static_cast<long long>(std::ceil((max.y() - min.y()) / options.resolution));
  if (w < 1 || h < 1 || w * h > OccupancyGrid::kMaxCells) {
    throw Error(ErrorCode::kInvalidArgument,
                "map extent must span 1 to " + std::to_string(OccupancyGrid::kMaxCells) + " cells at this resolution");
  }
  geometry_ = OccupancyGrid(static_cast<int>(w), static_cast<int>(h), options.resolution, min, OccupancyGrid::kUnknown);
  log_odds_.assign(static_cast<size_t>(w) * h, 0.0f);
  seen_.assign(log_odds_.size(), 0);
}

OccupancyGridMapper::OccupancyGridMapper(const OccupancyGrid& geometry, const MapperOptions& options)
    : geometry_(geometry.width(), geometry.height(), geometry.resolution(), geometry.origin(), OccupancyGrid::kUnknown),
      o_(options),
      log_odds_(geometry.cells().size(), 0.0f),
      seen_(geometry.cells().size(), 0) {}

void OccupancyGridMapper::Update(size_t k, double log_odds, int himm) {
  if (o_.rule == MapUpdateRule::kHimm) {
    log_odds_[k] = static_cast<float>(std::clamp(static_cast<int>(log_odds_[k]) + himm, 0, 15));
  } else {
    log_odds_[k] = static_cast<float>(std::clamp(log_odds_[k] + log_odds, o_.l_min, o_.l_max));
  }
  seen_[k] = 1;
}

void OccupancyGridMapper::AddScan(const Pose2& pose, const std::vector<float>& ranges, double angle_min,
                                  double increment, double range_max) {
  const double no_return = std::min(o_.max_range, range_max);
  const double reach = ScanReachOf(o_, ranges, no_return);
  for (size_t i = 0; i < ranges.size(); ++i) {
    const double r = ranges[i];
    if (!IsReading(r)) continue;
    const bool hit = r < no_return && r <= reach;
    const double length = TracedLength(o_, r, no_return, reach);
    if (length <= 0.0) continue;
    const double a = pose.theta + angle_min + i * increment;
    const Point2 from = pose.translation();
    const Point2 dir(std::cos(a), std::sin(a));
    const Point2 to = from + length * dir;
    // A reading measures the distance to a surface; a hair further along the beam is the cell
    // behind it (a reading ending exactly on a cell border would otherwise mark the free cell).
    const CellIndex end = geometry_.CellOf(to + 0.01 * geometry_.resolution() * dir);
    const bool end_inside = geometry_.Contains(end);
    ClearBeam(from, to,
              hit && end_inside ? static_cast<long>(geometry_.Flat(end)) : -1);  // the end cell is updated below
    if (hit && end_inside) Update(geometry_.Flat(end), o_.l_occupied, +3);
  }
}

void OccupancyGridMapper::ClearBeam(const Point2& from, const Point2& to, long skip) {
  // Amanatides & Woo in cell units, counting the cells to the end one. At an exact corner it
  // steps through one side cell where TraverseSegment visits both: one free observation more or
  // less on a hair-thin diagonal, for a walk a scan makes ~10^5 times.
  const double res = geometry_.resolution();
  const int w = geometry_.width(), h = geometry_.height();
  const Point2 a = (from - geometry_.origin()) / res, b = (to - geometry_.origin()) / res;
  int x = static_cast<int>(std::floor(a.x())), y = static_cast<int>(std::floor(a.y()));
  const int x1 = static_cast<int>(std::floor(b.x())), y1 = static_cast<int>(std::floor(b.y()));
  const Point2 d = b - a;
  const int sx = d.x() > 0 ? 1 : -1, sy = d.y() > 0 ? 1 : -1;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Fractions of the segment to the next vertical / horizontal cell border, and per cell.
  double tx = d.x() != 0.0 ? ((sx > 0 ? x + 1 : x) - a.x()) / d.x() : kInf;
  double ty = d.y() != 0.0 ? ((sy > 0 ? y + 1 : y) - a.y()) / d.y() : kInf;
  const double dtx = d.x() != 0.0 ? 1.0 / std::abs(d.x()) : kInf;
  const double dty = d.y() != 0.0 ? 1.0 / std::abs(d.y()) : kInf;
  for (int n = std::abs(x1 - x) + std::abs(y1 - y);; --n) {
    if (x >= 0 && y >= 0 && x < w && y < h) {
      const long k = static_cast<long>(y) * w + x;
      if (k != skip) Update(static_cast<size_t>(k), o_.l_free, -1);
    }
    if (n <= 0) break;
    if (tx < ty) {
      x += sx;
      tx += dtx;
    } else {
      y += sy;
      ty += dty;
    }
  }
}

void OccupancyGridMapper::AddSonar(const Pose2& sensor, double range, double half_angle, double max_range) {
  if (!std::isfinite(range) || range <= 0.0 || !(half_angle > 0.0) || !sensor.finite()) return;
  const bool hit = range < max_range;
  const double reach = std::min(range, max_range);
  const double res = geometry_.resolution();
  if (o_.rule == MapUpdateRule::kHimm) {
    // Borenstein: the cells on the acoustic axis only.
    const Point2 dir(std::cos(sensor.theta), std::sin(sensor.theta));
    const Point2 from = sensor.translation(), to = from + reach * dir;
    const CellIndex end = geometry_.CellOf(to + 0.01 * res * dir);
    TraverseSegment(geometry_, from, to, [&](const CellIndex& c, double) {
      if (geometry_.Contains(c) && !(hit && c == end)) Update(geometry_.Flat(c), 0.0, -1);
      return true;
    });
    if (hit && geometry_.Contains(end)) Update(geometry_.Flat(end), 0.0, +3);
    return;
  }
  // Elfes' cone: cells within the cone up to the reading; free short of the arc, occupied on it
  // (an arc of +-1.5 cells), each weighted by (1 - (beta/alpha)^2) so the axis counts most.
  const double tolerance = 1.5 * res;
  const int r = static_cast<int>(std::ceil((reach + tolerance) / res));
  const CellIndex c0 = geometry_.CellOf(sensor.translation());
  for (int y = c0.y - r; y <= c0.y + r; ++y) {
    for (int x = c0.x - r; x <= c0.x + r; ++x) {
      if (!geometry_.Contains({x, y})) continue;
      const Point2 d = geometry_.CellCenter({x, y}) - sensor.translation();
      const double rho = d.norm();
      if (rho > reach + tolerance || rho < 1e-9) continue;
      const double beta = std::abs(NormalizeAngle(std::atan2(d.y(), d.x()) - sensor.theta));
      if (beta > half_angle) continue;
      const double weight = 1.0 - (beta / half_angle) * (beta / half_angle);
      if (hit && std::abs(rho - range) <= tolerance) {
        Update(geometry_.Flat({x, y}), weight * o_.l_occupied, 0);
      } else if (rho < reach - tolerance) {
        Update(geometry_.Flat({x, y}), weight * o_.l_free_sonar * (1.0 - rho / (reach + tolerance)), 0);
      }
    }
  }
}

void OccupancyGridMapper::FuseLocalMap(const OccupancyGrid& local, const Pose2& local_pose) {
  if (o_.rule != MapUpdateRule::kLogOdds)
    throw Error(ErrorCode::kFailedPrecondition, "local map fusion needs the log-odds rule");
  const double lr = local.resolution();
  const Pose2 to_local = local_pose.inverse();
  // The global cells the local map's footprint can touch.
  Point2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const Point2& corner :
       {Point2(0, 0), Point2(local.size_x(), 0), Point2(0, local.size_y()), Point2(local.size_x(), local.size_y())}) {
    const Point2 w = local_pose * corner;
    lo = lo.cwiseMin(w);
    hi = hi.cwiseMax(w);
  }
  const CellIndex a = geometry_.CellOf(lo), b = geometry_.CellOf(hi);
  for (int y = std::max(0, a.y); y <= std::min(geometry_.height() - 1, b.y); ++y) {
    for (int x = std::max(0, a.x); x <= std::min(geometry_.width() - 1, b.x); ++x) {
      // The global cell's centre in local cell coordinates (centres at half-integers).
      const Point2 p = to_local * geometry_.CellCenter({x, y});
      const double fx = p.x() / lr - 0.5, fy = p.y() / lr - 0.5;
      const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
      double sum = 0.0, weights = 0.0;
      for (int j = 0; j <= 1; ++j) {
        for (int i = 0; i <= 1; ++i) {
          const CellIndex c{x0 + i, y0 + j};
          if (!local.Contains(c) || local.at(c) < 0) continue;
          // Bilinear weight: the area of the opposite sub-rectangle (seed 002 prints the distances
          // to the cell itself, which would weight the farthest cell most).
          const double w = (1.0 - std::abs(fx - c.x)) * (1.0 - std::abs(fy - c.y));
          sum += w * local.at(c) / 100.0;
          weights += w;
        }
      }
      if (weights < 1e-9) continue;
      const double prob = std::clamp(sum / weights, 0.02, 0.98);
      Update(geometry_.Flat({x, y}), std::log(prob / (1.0 - prob)), 0);
    }
  }
}

OccupancyGrid OccupancyGridMapper::ToGrid() const {
  OccupancyGrid g = geometry_;
  for (int y = 0; y < g.height(); ++y)
    for (int x = 0; x < g.width(); ++x) {
      const size_t k = g.Flat({x, y});
      if (!seen_[k]) continue;
      const double p =
          o_.rule == MapUpdateRule::kHimm ? log_odds_[k] / 15.0 : 1.0 - 1.0 / (1.0 + std::exp(log_odds_[k]));
      g.set({x, y}, static_cast<int8_t>(std::lround(100.0 * p)));
    }
  return g;
}

}  // namespace navd::mapping
