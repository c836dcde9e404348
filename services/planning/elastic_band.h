#pragma once
// Elastic-band smoothing of a path (the R-snake of book chapter 9, section 3): the path is a chain
// of points that moves down the gradient of an energy, internal (elastic contraction that shortens
// and evens the chain, curvature that straightens it) plus external (repulsion from obstacles
// closer than an influence distance). The chapter gives the energy's form (Eqs. 1-3) but not its
// terms; these are the usual ones of Quinlan and Khatib's elastic bands. A point moves only where
// both of its segments stay free on the costmap, so the band never enters inflated space; the
// end points stay. Metres, map frame.
#include <vector>

#include "services/common/pose2.h"
#include "services/planning/costmap.h"

namespace navd::planning {

struct ElasticBandOptions {
  double spacing = 0.1;  // m between chain points
  int iterations = 150;
  double contraction = 0.4;  // weight of the elastic force (toward the neighbours' midpoint)
  double curvature = 0.1;    // weight of the curvature force (fourth difference)
  double obstacle = 0.3;     // weight of the repulsion
  double influence = 0.6;    // m: obstacles farther than this do not push
};

std::vector<Point2> ElasticBand(const Costmap& costmap, const std::vector<Point2>& path,
                                const ElasticBandOptions& options = {});

// Largest turn between consecutive segments, radians (0 for a straight path).
double MaxTurn(const std::vector<Point2>& path);

}  // namespace navd::planning
