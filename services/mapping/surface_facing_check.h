#pragma once
// Which side of its walls a scan match puts the robot on. A laser sees a wall from the side it
// stands on; two scans of the same wall, correctly placed, see it from the same side. A corner or
// a corridor matched the wrong way round (an outer corner laid on an inner one, the robot put
// inside a block the reference's scans only saw from outside) fits the walls' points as well as
// the right pose, but from behind: the correlative score cannot tell, the walls' facing can. Only
// returns on a straight run of wall count: a chair's leg or a pillar is seen from every side.
// Map frame, metres.
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "services/common/pose2.h"

namespace navd::mapping {

// A scan's returns in beam order (sensor frame) and the sensor's pose in the map frame.
struct PlacedReturns {
  Pose2 pose;
  const std::vector<Point2>* points = nullptr;
};

struct SurfaceFacingOptions {
  double resolution = 0.1;  // m: a return is compared with the reference's walls in its cell and the eight around
  // A return's wall: the line through the returns `span` beams either side, when both lie within
  // max_reach (m) of it and it lies within max_offset (m) of the line between them.
  int span = 2;
  double max_reach = 0.3;
  double max_offset = 0.02;
};

class SurfaceFacingCheck {
 public:
  explicit SurfaceFacingCheck(const std::vector<PlacedReturns>& reference, const SurfaceFacingOptions& options = {});
  // Of the wall returns of `scan` (beam order, sensor frame) placed at `pose` that land on the
  // reference's walls, the share where every reference wall around faces the other way (more
  // than a right angle off): about 0 for a right match, about 1 for a match from behind. 0 when
  // none lands on them.
  double BehindShare(const Pose2& pose, const std::vector<Point2>& scan) const;

 private:
  // Per return of `points` (sensor frame), its wall's unit normal towards the sensor, or zero.
  std::vector<Point2> Normals(const std::vector<Point2>& points) const;
  int64_t Key(const Point2& p) const;
  // Facings are kept as one of kSectors directions (45 degrees each), one bit each.
  static constexpr int kSectors = 8;
  static int Sector(const Point2& normal);
  SurfaceFacingOptions o_;
  // Per cell: the facings (map frame) of the reference's wall returns in it. A thin wall seen
  // from both sides holds both, so a return on either face finds its own.
  std::unordered_map<int64_t, uint8_t> facings_;
};

}  // namespace navd::mapping
