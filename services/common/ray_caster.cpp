#include "services/common/ray_caster.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "services/common/distance_field.h"

namespace navd {
namespace {

constexpr int kTileShift = 3;  // 8 x 8 cells, one 64-bit word: 0.4 m at 5 cm
constexpr int kTile = 1 << kTileShift;
// A cell's centre D cells from the nearest obstacle centre is at least D - sqrt(2) cells from any
// point of that obstacle's square: half a diagonal for each square.
constexpr float kSafeMargin = 1.4143f;
// Ray parameters in cells as fixed point with 32 fraction bits.
using Fixed = int64_t;
constexpr double kFixedOne = 4294967296.0;
// Rays are walked at most 2^15 cells (1.6 km at 5 cm); a per-cell step longer than 2^16 cells, or
// a first crossing beyond 2^28, is never reached. With leaps of at most 255 tiles of 8 cells the
// sums stay below 2^61.
constexpr double kMaxCells = 32768.0;
constexpr double kMaxStep = 65536.0;
constexpr double kMaxFirst = 268435456.0;
// Two boundary crossings closer than this are one crossing through a corner: 1e-9 cells, as
// TraverseSegment's tolerance.
constexpr Fixed kCornerFixed = 4;

// Rounded to nearest, half away from zero, as llround, without its library call: every value
// converted is at least 0 (the ray's direction is finite), and below 2^52, where adding one half is
// exact, for every parameter a walk of kMaxCells reaches; larger ones (unreached first crossings)
// may round one unit of 2^-32 cell up.
Fixed ToFixed(double cells) {
  return static_cast<Fixed>(cells * kFixedOne + 0.5);  // NOLINT(bugprone-incorrect-roundings): never negative
}
// A value in [0, 1] as a 2.62 fixed-point number (a signed conversion: no unsigned fix-up code).
uint64_t ToFraction(double v) { return static_cast<uint64_t>(static_cast<int64_t>(v * 4611686018427387904.0)); }

// How many of the crossings first, first + step, first + 2 step, ... come before t. `per` is
// 1 / step as a 2.62 fraction of a cell, for an estimate by one multiplication (no division: this
// is on the walk's critical path), which exact integer comparisons then correct by one or two.
int CrossingsBefore(Fixed t, Fixed first, Fixed step, uint64_t per) {
  if (first >= t) return 0;
  const auto estimate = static_cast<unsigned __int128>(static_cast<uint64_t>(t - first)) * per;
  // (t - first) / step rounded up: almost always floor + 1 (cells x 2^32 x 2^62 / 2^94 = crossings).
  int64_t k = static_cast<int64_t>(static_cast<uint64_t>(estimate >> 94)) + 1;
  while (k > 0 && first + (k - 1) * step >= t) --k;
  while (first + k * step < t) ++k;
  return static_cast<int>(k);
}

}  // namespace

RayCaster::RayCaster(OccupancyGrid grid) : grid_(std::move(grid)), inv_resolution_(1.0 / grid_.resolution()) {
  const DistanceField field(grid_);
  clearance_.resize(field.values().size());
  const double inv = 1.0 / grid_.resolution();
  for (size_t i = 0; i < clearance_.size(); ++i) {
    const double d = field.values()[i];
    clearance_[i] = std::isfinite(d) ? static_cast<float>(d * inv) : 1e9f;
  }
  const int width = grid_.width(), height = grid_.height();
  // The map's edge is a wall too: clearance can be no larger than the distance to just outside it.
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const int edge = std::min({x + 1, y + 1, width - x, height - y});
      float& c = clearance_[static_cast<size_t>(y) * width + x];
      c = std::min(c, static_cast<float>(edge));
    }
  }
  // Tiles reaching past the padded grid are walls there, so a leap never lands outside them.
  const int padded_width = width + 2, padded_height = height + 2;
  tile_stride_ = (padded_width + kTile - 1) / kTile;
  const int tile_rows = (padded_height + kTile - 1) / kTile;
  tiles_.assign(static_cast<size_t>(tile_stride_) * tile_rows, 0);
  for (int y = 0; y < tile_rows * kTile; ++y) {
    for (int x = 0; x < tile_stride_ * kTile; ++x) {
      const bool inside = x >= 1 && y >= 1 && x <= width && y <= height;
      if (inside && !grid_.IsOccupied({x - 1, y - 1})) continue;
      tiles_[static_cast<size_t>(y >> kTileShift) * tile_stride_ + (x >> kTileShift)] |=
          uint64_t{1} << (((y & (kTile - 1)) << kTileShift) | (x & (kTile - 1)));
    }
  }
  // For each of the four directions a ray can head in, the side (in tiles) of the largest empty
  // square that has this tile at its trailing corner: the classic largest-square recurrence, run
  // from the far side. Tiles on the array's edge hold ring cells, so no square reaches past it.
  const int w = tile_stride_, h = tile_rows;
  empty_ahead_.assign(tiles_.size() * 4, 0);
  for (int q = 0; q < 4; ++q) {
    const int sx = (q & 1) ? -1 : 1, sy = (q & 2) ? -1 : 1;
    for (int j = 0; j < h; ++j) {
      const int y = sy > 0 ? h - 1 - j : j;
      for (int i = 0; i < w; ++i) {
        const int x = sx > 0 ? w - 1 - i : i;
        const size_t t = static_cast<size_t>(y) * w + x;
        if (tiles_[t]) continue;
        const int nx = x + sx, ny = y + sy;
        const bool inside = nx >= 0 && ny >= 0 && nx < w && ny < h;
        const auto ahead = [&](int ax, int ay) {
          return static_cast<int>(empty_ahead_[(static_cast<size_t>(ay) * w + ax) * 4 + q]);
        };
        const int side = inside ? 1 + std::min({ahead(nx, y), ahead(x, ny), ahead(nx, ny)}) : 1;
        empty_ahead_[t * 4 + q] = static_cast<uint8_t>(std::min(side, 255));
      }
    }
  }
}

double RayCaster::Clearance(const Point2& p) const {
  const CellIndex c = grid_.CellOf(p);
  if (!grid_.Contains(c)) return 0.0;
  return clearance_[grid_.Flat(c)] * grid_.resolution();
}

double RayCaster::Cast(const Point2& origin, double angle, double max_range) const {
  return Cast(origin, Point2(std::cos(angle), std::sin(angle)), max_range);
}

double RayCaster::Cast(const Point2& origin, const Point2& dir, double max_range) const {
  if (!(max_range > 0.0)) return max_range;
  const double res = grid_.resolution();
  // Everything below is in cells; the same arithmetic as CellOf and TraverseSegment, so a ray
  // running along a cell boundary walks the same side of it as the reference walk.
  const double lx = (origin.x() - grid_.origin().x()) / res;
  const double ly = (origin.y() - grid_.origin().y()) / res;
  if (!(lx >= 0.0 && ly >= 0.0 && lx < grid_.width() && ly < grid_.height())) return 0.0;
  const double dx = dir.x(), dy = dir.y();
  const int sx = dx > 0 ? 1 : -1, sy = dy > 0 ? 1 : -1;
  const double fx = std::floor(lx), fy = std::floor(ly);
  int cx = static_cast<int>(fx) + 1, cy = static_cast<int>(fy) + 1;  // padded
  const uint64_t* tiles = tiles_.data();
  const uint8_t* empty_ahead = empty_ahead_.data();
  const int quadrant = (sx > 0 ? 0 : 1) | (sy > 0 ? 0 : 2);
  const size_t tile_stride = static_cast<size_t>(tile_stride_);
  auto tile_of = [&](int x, int y) {
    return tiles[static_cast<size_t>(y >> kTileShift) * tile_stride + (x >> kTileShift)];
  };
  auto wall = [&](int x, int y) {
    return (tile_of(x, y) >> (((y & (kTile - 1)) << kTileShift) | (x & (kTile - 1)))) & 1;
  };
  if (wall(cx, cy)) return 0.0;
  // The walk runs in fixed point (cells x 2^32): comparing and stepping integers keeps the chain
  // from one cell to the next a few cycles long, and sums of steps are exact, so a leap lands on
  // exactly the crossing the cell-by-cell walk would reach.
  const double max_t = std::min(max_range * inv_resolution_, kMaxCells);
  const Fixed max_tf = ToFixed(max_t);
  const double adx = std::abs(dx), ady = std::abs(dy);
  // Per-cell steps beyond kMaxStep cells are never taken within kMaxCells: clamped, so leaps of up
  // to 255 tiles cannot overflow.
  const double rdx = 1.0 / dx, rdy = 1.0 / dy;  // +-inf along an axis
  const Fixed step_x = ToFixed(std::min(std::abs(rdx), kMaxStep));
  const Fixed step_y = ToFixed(std::min(std::abs(rdy), kMaxStep));
  const uint64_t per_x = ToFraction(adx), per_y = ToFraction(ady);
  const double first_x = dx != 0 ? ((dx > 0 ? fx + 1 : fx) - lx) * rdx : kMaxFirst;
  const double first_y = dy != 0 ? ((dy > 0 ? fy + 1 : fy) - ly) * rdy : kMaxFirst;
  Fixed t_x = ToFixed(std::min(first_x, kMaxFirst)), t_y = ToFixed(std::min(first_y, kMaxFirst));
  const double to_metres = res / kFixedOne;
  // One cell step across the nearer boundary (not a corner); returns the ray parameter there.
  // Which boundary comes first is a coin toss for most rays: chosen without a branch.
  auto step_across = [&] {
    const bool along_x = t_x < t_y;
    const Fixed t = along_x ? t_x : t_y;
    cx += along_x ? sx : 0;
    cy += along_x ? 0 : sy;
    t_x += along_x ? step_x : 0;
    t_y += along_x ? 0 : step_y;
    return t;
  };
  while (true) {
    const int tx = cx >> kTileShift, ty = cy >> kTileShift;
    const int side = empty_ahead[(static_cast<size_t>(ty) * tile_stride + tx) * 4 + quadrant];
    if (side > 0) {
      // No wall in the square of tiles ahead of this one: move to its last cell along the ray in
      // one go, taking exactly the crossings a cell walk would take before it leaves (none of them
      // can hit anything), and let the cell step below leave it with the usual corner rule.
      const int nx = sx > 0 ? ((tx + side) << kTileShift) - cx : cx - ((tx - side + 1) << kTileShift) + 1;
      const int ny = sy > 0 ? ((ty + side) << kTileShift) - cy : cy - ((ty - side + 1) << kTileShift) + 1;
      const Fixed exit_x = t_x + (nx - 1) * step_x, exit_y = t_y + (ny - 1) * step_y;
      if (std::min(exit_x, exit_y) > max_tf) return max_range;
      int kx = nx - 1, ky = ny - 1;
      if (exit_x < exit_y - kCornerFixed) {
        ky = CrossingsBefore(exit_x - kCornerFixed, t_y, step_y, per_y);
      } else if (exit_y < exit_x - kCornerFixed) {
        kx = CrossingsBefore(exit_y - kCornerFixed, t_x, step_x, per_x);
      }
      cx += sx * kx;
      cy += sy * ky;
      t_x += kx * step_x;
      t_y += ky * step_y;
    } else {
      // A tile with walls: walk it cell by cell with its bits at hand until the ray hits one,
      // leaves the tile (then look at the next tile) or meets a corner (taken below).
      const uint64_t bits = tiles[static_cast<size_t>(ty) * tile_stride + tx];
      bool left = false;
      while (std::abs(t_x - t_y) > kCornerFixed) {
        const Fixed t = step_across();
        if (t > max_tf) return max_range;
        if (((cx >> kTileShift) ^ tx) | ((cy >> kTileShift) ^ ty)) {
          if (wall(cx, cy)) return t * to_metres;
          left = true;
          break;
        }
        if ((bits >> (((cy & (kTile - 1)) << kTileShift) | (cx & (kTile - 1)))) & 1) return t * to_metres;
      }
      if (left) continue;
    }
    if (std::abs(t_x - t_y) <= kCornerFixed) {
      // Through a corner: the two side cells count too, so nothing slips between diagonal walls.
      const Fixed tc = std::min(t_x, t_y);
      if (tc > max_tf) return max_range;
      if (wall(cx + sx, cy) || wall(cx, cy + sy)) return tc * to_metres;
      cx += sx;
      cy += sy;
      t_x += step_x;
      t_y += step_y;
      if (wall(cx, cy)) return tc * to_metres;
    } else {
      const Fixed t = step_across();
      if (t > max_tf) return max_range;
      if (wall(cx, cy)) return t * to_metres;
    }
  }
}

double RayCaster::CastOpenEdge(const Point2& origin, const Point2& dir, double max_range) const {
  const double r = Cast(origin, dir, max_range);
  // A hit lies on the boundary of the cell the ray enters there, to within 1e-9 cells: a step of
  // 1e-4 cells on is inside that cell (for a ring cell, off the grid). Only a ray through a grid
  // corner exactly, touching an edge wall cell at its corner, is misjudged.
  if (r >= max_range) return r;
  const Point2 beyond = (origin + dir * (r + 1e-4 * grid_.resolution()) - grid_.origin()) * inv_resolution_;
  if (!(beyond.x() >= 0.0 && beyond.y() >= 0.0 && beyond.x() < grid_.width() && beyond.y() < grid_.height()))
    return max_range;
  return r;
}

double RayCaster::CastOpenEdge(const Point2& origin, double angle, double max_range) const {
  return CastOpenEdge(origin, Point2(std::cos(angle), std::sin(angle)), max_range);
}

bool RayCaster::DiscHitsWall(const Point2& p, double radius) const {
  const CellIndex c = grid_.CellOf(p);
  if (!p.allFinite() || !grid_.Contains(c)) return true;
  // Clear by a cell's diagonal more than the radius: no occupied square can reach the disc.
  if ((clearance_[grid_.Flat(c)] - kSafeMargin) * grid_.resolution() > radius) return false;
  return grid_.DiscHitsObstacle(p, radius);
}

}  // namespace navd
