#pragma once
// The free space of a costmap cut into convex cells joined by doorways: seed 000's "convex
// navigation grid" (section 4.1.1), also the convex polygons of seed 004's meadow map and the
// places of book chapter 1's topological graph. Map frame, metres.
//
// Construction follows seed 000's Table 1 on the costmap's raster:
//  1. contracted map: the cells farther than the costmap's inflation radius plus `margin` from
//     every obstacle in x or in y (obstacles grown by a square, so walls keep sharp corners);
//  2. map-curve intersection grid: every boundary of the contracted map is axis-parallel on a
//     raster, so extending each boundary segment to a full line gives a rectilinear grid whose
//     rectangles are wholly free or wholly blocked (the seed's step 3 for slanted segments has
//     nothing to do: slanted walls arrive as staircases);
//  3. outside cells (blocked rectangles) are removed;
//  4. cells are joined while the union stays convex (for rectangles: they share a whole side),
//     processed in order, rows first or columns first, whichever leaves fewer cells.
// A straight segment between two points of one cell is collision-free: a cell is convex and holds
// only contracted-free raster cells.
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "services/common/polygon.h"
#include "services/planning/costmap.h"

namespace navd::planning {

struct ConvexCell {
  Point2 min, max;                // the axis-aligned rectangle, metres
  std::vector<int32_t> doorways;  // indices into ConvexCellMap::doorways()
  Point2 centre() const { return 0.5 * (min + max); }
};

// The common side two cells share (positive length): a way from one to the other.
struct Doorway {
  int32_t cells[2];
  Point2 a, b;  // ends of the shared segment
  Point2 middle() const { return 0.5 * (a + b); }
  int32_t other(int32_t cell) const { return cells[0] == cell ? cells[1] : cells[0]; }
};

// Where a query point joins the cells: the cell and the point inside it (the query point itself,
// or the nearest point of a nearby cell when the query point lies in the margin).
struct CellEntry {
  int32_t cell = -1;
  Point2 point = Point2::Zero();
};

class ConvexCellMap {
 public:
  ConvexCellMap(const Costmap& costmap, double margin);

  const std::vector<ConvexCell>& cells() const { return cells_; }
  const std::vector<Doorway>& doorways() const { return doorways_; }
  double margin() const { return margin_; }
  // The point at fraction t (0..1) along a doorway, its ends kept half a raster cell away so paths
  // do not graze the corners of the cells around it.
  Point2 DoorwayPoint(int32_t door, double t) const;
  // A path crossing `door` at q (a DoorwayPoint) from cell `from`: q moved a quarter raster cell
  // into `from`, and into the other cell. Legs then join interior points of one convex cell, so no
  // leg runs along a cell's side, where the costmap's cells beyond may be lethal.
  std::pair<Point2, Point2> Crossing(int32_t door, int32_t from, const Point2& q) const;
  // The cell holding p, or -1.
  int32_t CellAt(const Point2& p) const;
  // The cell holding `p`, or else the nearest cell within `reach` metres whose nearest point the
  // robot can drive to straight (costmap segment free). Throws navd::Error(kNotFound) naming
  // `what` ("start", "goal") when there is none.
  CellEntry Enter(const Costmap& costmap, const Point2& p, double reach, const std::string& what) const;

 private:
  double margin_;
  int width_, height_;
  double resolution_;
  Point2 origin_;
  std::vector<int32_t> label_;  // raster cell -> convex cell, -1 outside
  std::vector<ConvexCell> cells_;
  std::vector<Doorway> doorways_;
};

// The decomposition of the latest costmap, shared by the planners that use one: built on first use
// per map (and margin), reused while that map is in service. Thread-safe.
class ConvexCellMapCache {
 public:
  std::shared_ptr<const ConvexCellMap> Get(const Costmap& costmap, double margin);

 private:
  std::mutex mutex_;
  std::weak_ptr<const OccupancyGrid> grid_;  // identity of the map (an expired one never matches a new map)
  CostmapOptions costmap_options_;
  std::shared_ptr<const ConvexCellMap> map_;
};

}  // namespace navd::planning
