#pragma once
// Per-thread scratch arrays for grid searches, reused across requests: a generation stamp marks
// which entries belong to the current search, so starting one costs O(1) instead of clearing
// arrays the size of the map (which dominated short queries on large maps).
#include <cstdint>
#include <limits>
#include <vector>

namespace navd::planning {

class SearchWorkspace {
 public:
  // Prepares for a search over `cells` cells and returns the workspace of the calling thread.
  static SearchWorkspace& ForThisThread(size_t cells) {
    thread_local SearchWorkspace ws;
    ws.Begin(cells);
    return ws;
  }

  double g(size_t i) const {
    return (nodes_[i].mark >> 1) == generation_ ? nodes_[i].g : std::numeric_limits<double>::infinity();
  }
  int32_t parent(size_t i) const { return nodes_[i].parent; }
  bool closed(size_t i) const { return nodes_[i].mark == 2 * generation_ + 1; }
  void Set(size_t i, double g, int32_t parent) {
    Node& n = nodes_[i];
    if ((n.mark >> 1) != generation_) n.mark = 2 * generation_;
    n.g = g;
    n.parent = parent;
  }
  // Only for cells already Set in this search.
  void Close(size_t i) { nodes_[i].mark = 2 * generation_ + 1; }

  // The same for searches that count costs in fixed-point integers, kept in g's slot.
  static constexpr int64_t kInfiniteCost = std::numeric_limits<int64_t>::max();
  int64_t cost(size_t i) const { return (nodes_[i].mark >> 1) == generation_ ? nodes_[i].cost : kInfiniteCost; }
  void SetCost(size_t i, int64_t cost, int32_t parent) {
    Node& n = nodes_[i];
    if ((n.mark >> 1) != generation_) n.mark = 2 * generation_;
    n.cost = cost;
    n.parent = parent;
  }

 private:
  // One 16-byte record per cell: a neighbour's whole state is one cache access.
  struct Node {
    union {
      double g;
      int64_t cost;
    };
    int32_t parent;
    uint32_t mark;  // 2 * generation when touched in that search, + 1 once closed
  };

  void Begin(size_t cells) {
    if (nodes_.size() < cells) nodes_.resize(cells, Node{{0.0}, -1, 0});
    if (++generation_ >= (1u << 31)) {  // marks would overflow: start afresh
      for (auto& n : nodes_) n.mark = 0;
      generation_ = 1;
    }
  }

  std::vector<Node> nodes_;
  uint32_t generation_ = 0;
};

}  // namespace navd::planning
