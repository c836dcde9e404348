#pragma once
// A 2-D occupancy grid in the map frame, laid out like nav_msgs/OccupancyGrid: row-major from the
// lower-left cell, values -1 (unknown) or 0..100 (occupancy probability in percent).
#include <cstdint>
#include <string>
#include <vector>

#include "services/common/pose2.h"

namespace navd {

struct CellIndex {
  int x = 0;
  int y = 0;
  bool operator==(const CellIndex&) const = default;
};

class OccupancyGrid {
 public:
  static constexpr int8_t kUnknown = -1;
  static constexpr int8_t kFree = 0;
  static constexpr int8_t kOccupied = 100;
  // Cells at or above this value count as obstacles (map_server's occupied_thresh of 0.65).
  static constexpr int8_t kOccupiedThreshold = 65;
  // Known cells under this value count as free space (map_server's free_thresh of 0.196). Maps made
  // in memory (the mapper's probabilities, a SLAM run's map) hold graded values: a free cell seen
  // by many clamped misses holds a few percent, not kFree.
  static constexpr int8_t kFreeThreshold = 20;
  static constexpr bool IsFreeValue(int8_t value) { return value >= kFree && value < kFreeThreshold; }
  // Largest grid navd accepts (e.g. 5000 x 5000): planners allocate several bytes per cell per
  // request, so bigger maps would exhaust memory under concurrent requests.
  static constexpr long long kMaxCells = 25'000'000;

  OccupancyGrid() = default;
  // resolution: metres per cell; origin: map-frame position of cell (0,0)'s lower-left corner.
  OccupancyGrid(int width, int height, double resolution, Point2 origin, int8_t fill = kFree);

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution() const { return resolution_; }
  const Point2& origin() const { return origin_; }
  const std::vector<int8_t>& cells() const { return cells_; }
  bool empty() const { return cells_.empty(); }

  bool Contains(const CellIndex& c) const { return c.x >= 0 && c.y >= 0 && c.x < width_ && c.y < height_; }
  int8_t at(const CellIndex& c) const { return cells_[Flat(c)]; }
  void set(const CellIndex& c, int8_t v) { cells_[Flat(c)] = v; }
  bool IsOccupied(const CellIndex& c) const { return at(c) >= kOccupiedThreshold; }
  size_t Flat(const CellIndex& c) const { return static_cast<size_t>(c.y) * width_ + c.x; }

  // The cell containing p (may lie outside the grid; check Contains). Far-away and non-finite
  // points map to cells far outside rather than overflowing.
  CellIndex CellOf(const Point2& p) const;
  Point2 CellCenter(const CellIndex& c) const;
  // Metres from p to the nearest point of cell c's square (0 inside it): a wall's cells reach half
  // a cell beyond their centres, and footprint tests that used the centres missed corners by that.
  double DistanceToCell(const Point2& p, const CellIndex& c) const;
  // True when p lies inside the grid's extent.
  bool ContainsPoint(const Point2& p) const { return Contains(CellOf(p)); }
  double size_x() const { return width_ * resolution_; }
  double size_y() const { return height_ * resolution_; }

  // True when a disc of `radius` metres centred at p overlaps an occupied cell or leaves the grid
  // (the robot footprint test of the simulator and of world checks).
  bool DiscHitsObstacle(const Point2& p, double radius) const;

  // Marks every cell whose centre lies in the axis-aligned box [min, max] (map frame) as occupied.
  void FillBox(const Point2& min, const Point2& max, int8_t value = kOccupied);
  // Marks every cell whose centre lies within `radius` of `centre` (map frame) as occupied.
  void FillDisc(const Point2& centre, double radius, int8_t value = kOccupied);

 private:
  int width_ = 0;
  int height_ = 0;
  double resolution_ = 0.05;
  Point2 origin_ = Point2::Zero();
  std::vector<int8_t> cells_;
};

}  // namespace navd
