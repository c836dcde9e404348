#pragma once
// Where to explore next on a map being built, and how to get there through known free space.
// Three methods:
//  - greedy (seed 002 section 2.3): the minimum-cost path to the nearest unexplored cell, each
//    cell costing by its occupancy;
//  - frontier (Yamauchi 1997, seed 002's frontiers): free cells bordering unknown space grouped
//    into frontiers; small ones (sensor noise) ignored; the nearest frontier by path, aiming at
//    its cell nearest its centre;
//  - Voronoi Fast Marching (book chapter 4, case II): W = the obstacles' extended Voronoi
//    transform, VT = the same of the places already visited, WV = 0.5 VT + W; the goal is the
//    frontier cell of largest WV ("the most unexplored region that is in a free space") and the
//    path follows Fast Marching over WV.
// A cell is traversable when it is known free and farther than the robot's clearance from every
// known obstacle (or, on a way the robot came by, than the squeeze clearance); unknown space is
// never crossed. Map frame, metres.
#include <optional>
#include <vector>

#include "services/common/occupancy_grid.h"

namespace navd::navigation {

enum class ExplorationMethod { kGreedy, kFrontier, kVoronoiFastMarching };

struct ExplorationOptions {
  double clearance = 0.3;  // m from obstacles the robot's centre keeps
  // Ways the robot came by, its past positions in order: within squeeze_radius of the segments
  // between them, cells farther than squeeze_clearance from obstacles are traversable too (a
  // way walls seen better have narrowed). Goals keep the full clearance.
  std::vector<Point2> squeeze_trail;
  double squeeze_clearance = 0.25;  // m
  double squeeze_radius = 0.3;      // m
  int free_below = 25;              // map values below this are known free (0..100)
  int min_frontier_cells = 6;       // frontier method: smaller frontiers are ignored
  double occupancy_cost = 4.0;      // greedy: extra cost per cell at occupancy 100
  double w_saturation = 1.5;        // m: W reaches 1 this far from obstacles
  double vt_saturation = 4.0;       // m: VT reaches 1 this far from visited places
  // Goals given up on (reached without the frontier going away, or no progress): frontier cells
  // within exclusion_radius of them are not chosen again.
  std::vector<Point2> excluded;
  double exclusion_radius = 0.5;  // m
};

struct ExplorationStep {
  Point2 goal = Point2::Zero();
  std::vector<Point2> path;  // robot first, goal last
  int frontier_cells = 0;    // frontier cells reachable now
};

// The next goal and path, or nullopt when no reachable frontier remains (the map is complete as
// far as the robot can drive). `visited`: the robot's past positions (VFM only).
std::optional<ExplorationStep> NextExplorationStep(const OccupancyGrid& map, const Pose2& robot,
                                                   ExplorationMethod method, const std::vector<Point2>& visited,
                                                   const ExplorationOptions& options = {});

// Name <-> method ("greedy", "frontier", "vfm"); throws navd::Error(kInvalidArgument) naming the
// known ones.
ExplorationMethod ParseExplorationMethod(const std::string& name);

}  // namespace navd::navigation
