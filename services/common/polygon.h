#pragma once
// Closed polygons ("map curves", seed 000 section 4.1.1) for polygon worlds: validation and
// rasterisation into an occupancy grid. Vertices in metres, map frame, either orientation.
#include <optional>
#include <string>
#include <vector>

#include "services/common/occupancy_grid.h"

namespace navd {

using Polygon = std::vector<Point2>;

// Why `polygon` is not a simple closed curve (fewer than 3 vertices, zero area, or two edges that
// cross or touch other than at their shared vertex), or nullopt when it is one.
std::optional<std::string> PolygonDefect(const Polygon& polygon);

// True when p lies inside the polygon (even-odd rule).
bool PolygonContains(const Polygon& polygon, const Point2& p);

// Euclidean distance from p to the segment a-b, metres.
double DistanceToSegment(const Point2& p, const Point2& a, const Point2& b);

// Distance from p to the polygon's boundary (its nearest edge), metres, inside or out.
double DistanceToBoundary(const Polygon& polygon, const Point2& p);

// Sets every cell whose centre lies inside the polygon, and every cell its edges pass through (so
// thin walls survive rasterisation), to `value`.
void FillPolygon(OccupancyGrid& grid, const Polygon& polygon, int8_t value = OccupancyGrid::kOccupied);

// Sets every cell whose centre lies outside the polygon, and the cells on its edges, to `value`:
// the polygon is the outline of the free space.
void FillOutsidePolygon(OccupancyGrid& grid, const Polygon& polygon, int8_t value = OccupancyGrid::kOccupied);

}  // namespace navd
