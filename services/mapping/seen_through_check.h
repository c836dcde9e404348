#pragma once
// Whether a scan saw through a place: its beams towards that place, and on either side of it,
// read farther than the place. A person who walked past while the robot scanned left returns in
// one node's scan where the nodes before and after it saw the wall behind; kept in the front end's
// local map, such returns give a bare corridor a landmark that moves, and the scan after slides
// along the corridor to fit it. Walls are not seen through: at a wall's edge the beam beside the
// place hits the wall, and along a wall at a grazing angle the beams on one side hit it nearer.
// Map frame, metres, radians.
#include <vector>

#include "services/common/pose2.h"

namespace navd::mapping {

struct SeenThroughOptions {
  // rad either side of the place within which every beam must read beyond it too (at least the
  // next beam each side): at a wall's edge or a door's jamb some of them hit the wall, and along a
  // wall at a grazing angle those on one side hit it nearer. An angle, not a count of beams, so a
  // scanner with beams a quarter of a degree apart is judged over the same sweep as a 1-degree one.
  double span = 0.035;
  // m beyond the place that every one of those beams must read: pose errors and range noise of a
  // few centimetres move a wall's hits by far less.
  double margin = 0.5;
  // m: places nearer (the scanner's own body) or farther are not judged. Far off, a heading error
  // of a few milliradians moves a place by more than a beam's spacing, and a 1-degree scanner's
  // beams 15 cm apart pass by a pole.
  double min_distance = 0.3;
  double max_distance = 8.0;
};

// One scan as a viewpoint: its laser pose in the map frame and its readings.
class SeenThroughCheck {
 public:
  // `ranges` at angle_min + i * angle_increment (rad, laser frame), kept by reference: they must
  // outlive the check. Readings at or beyond `no_return` (and non-readings, IsReading) say nothing
  // of what lies along the beam.
  SeenThroughCheck(const Pose2& pose, const std::vector<float>& ranges, double angle_min, double angle_increment,
                   double no_return, const SeenThroughOptions& options = {});
  // True when the beams towards `place` (map frame) and within `span` of it all read echoes
  // beyond it by the margin.
  bool SawThrough(const Point2& place) const;

 private:
  SeenThroughOptions o_;
  Pose2 inverse_;
  const std::vector<float>& ranges_;
  double angle_min_, angle_increment_, no_return_;
  size_t side_;      // beams either side of the one towards a place, from span
  bool whole_turn_;  // the beams sweep a whole turn: the first and last are neighbours
};

}  // namespace navd::mapping
