#pragma once
// D* Lite (Koenig and Likhachev, 2002), the incremental planner seed 002 compares with A*: it
// searches from the goal towards the robot, keeps its g/rhs values between calls, and after cells
// change (or the robot moves) repairs only what the change invalidates. 8-connected, octile
// heuristic, no corner cutting; costs in cells (1 and sqrt 2), kept exact as OctileCost.
#include <cstdint>
#include <utility>
#include <vector>

#include "services/planning/global_planner.h"
#include "services/planning/octile_cost.h"
#include "services/planning/quaternary_heap.h"

namespace navd::planning {

class DStarLite {
 public:
  // Takes the costmap's lethal cells as blocked; later changes arrive through SetBlocked.
  DStarLite(const Costmap& costmap, const CellIndex& start, const CellIndex& goal);

  // Brings the search up to date; returns false when the goal is unreachable. Throws
  // navd::Error(kDeadlineExceeded) when stop() turns true.
  bool ComputeShortestPath(const StopRequested& stop = {});
  // Marks a cell blocked or free (an obstacle appeared or went); call ComputeShortestPath after.
  void SetBlocked(const CellIndex& cell, bool blocked);
  // The robot moved to `start` (D* Lite's k_m bookkeeping keeps the queue valid).
  void MoveStart(const CellIndex& start);
  // The current shortest path, start first; empty when unreachable.
  std::vector<CellIndex> Path() const;
  // Length of the shortest path in cells (infinity when unreachable).
  double PathCost() const { return node_[Index(start_)].g.value(); }
  // Vertices expanded (made consistent) so far: the "states processed" of seed 002.
  uint64_t expansions() const { return expansions_; }

 private:
  struct Key {
    OctileCost k1, k2;
    bool operator<(const Key& o) const { return k1 < o.k1 || (k1 == o.k1 && k2 < o.k2); }
    bool operator==(const Key& o) const { return k1 == o.k1 && k2 == o.k2; }
  };

  int32_t Index(const CellIndex& c) const { return c.y * width_ + c.x; }
  CellIndex Cell(int32_t i) const { return {i % width_, i / width_}; }
  bool Free(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_ && !blocked_[y * width_ + x]; }
  // The octile distance from cell (x, y) to the start. The hot paths pass a cell's coordinates
  // along with its index: an index's coordinates cost an integer division.
  OctileCost HeuristicToStart(int x, int y) const { return OctileCost::Distance(x - start_.x, y - start_.y); }
  Key CalculateKey(int32_t s) const { return CalculateKey(s, s % width_, s / width_); }
  Key CalculateKey(int32_t s, int x, int y) const;
  void RecomputeRhs(int32_t u);  // rhs = min over edges of c + g (not for the goal)
  // Queued iff inconsistent, with its current key.
  void UpdateQueue(int32_t u) { UpdateQueue(u, u % width_, u / width_); }
  void UpdateQueue(int32_t u, int x, int y);
  void UpdateVertex(int32_t u);  // both
  void Push(int32_t u, int x, int y);
  // Calls f(neighbour, x, y, cost) for every traversable edge of u = (ux, uy) (cost an OctileCost
  // step).
  template <typename F>
  void ForEachEdge(int32_t u, int ux, int uy, F&& f) const;
  template <typename F>
  void ForEachEdge(int32_t u, F&& f) const {
    ForEachEdge(u, u % width_, u / width_, std::forward<F>(f));
  }

  int width_, height_;
  std::vector<uint8_t> blocked_;
  // A vertex's search state in one place: the search touches all of it at once, and over a large
  // grid each separate array cost a cache miss of its own.
  struct Node {
    OctileCost g = OctileCost::Infinite(), rhs = OctileCost::Infinite();
    Key queued_key;  // the key the vertex is queued with, valid while in_queue
    bool in_queue = false;
  };
  std::vector<Node> node_;
  QuaternaryHeap<Key> heap_;  // lazy deletion: entries whose key no longer matches are skipped
  CellIndex start_, goal_, last_;
  OctileCost km_;
  uint64_t expansions_ = 0;
};

// D* Lite as a one-shot planner for ComputePath (a fresh search per request).
class DStarLitePlanner : public GlobalPlanner {
 public:
  std::string name() const override { return "dstar_lite"; }
  std::string description() const override {
    return "D* Lite: incremental search from the goal (fresh per request; incremental in replanning)";
  }
  std::vector<PlannerOptionSpec> options() const override { return {}; }
  CellPath Plan(const Costmap& costmap, const CellIndex& start, const CellIndex& goal, const PlannerOptions& options,
                const StopRequested& stop) const override;
};

}  // namespace navd::planning
