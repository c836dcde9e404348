#pragma once
// A 4-ary min-heap of entries ordered by their `key` member, for grid searches: (key, node)
// pairs by default, or any entry type with a `key` (searches that pack the node into the key's
// low bits use 8-byte entries, twice as many per cache line). Against std::priority_queue's
// binary heap it halves the depth; pops of stale entries (nodes already closed) are left to the
// caller, as in lazy-deletion A*.
#include <cstdint>
#include <utility>
#include <vector>

namespace navd::planning {

template <typename Key>
struct KeyedNode {
  Key key;
  int32_t node;
};

template <typename Key = double, typename EntryType = KeyedNode<Key>>
class QuaternaryHeap {
 public:
  using Entry = EntryType;

  bool empty() const { return heap_.empty(); }
  size_t size() const { return heap_.size(); }
  void clear() { heap_.clear(); }
  const Entry& top() const { return heap_.front(); }

  void push(Key key, int32_t node) { push(Entry{key, node}); }
  void push(const Entry& e) {
    size_t i = heap_.size();
    heap_.push_back(e);
    while (i > 0) {
      const size_t parent = (i - 1) / 4;
      if (!(e.key < heap_[parent].key)) break;
      heap_[i] = heap_[parent];
      i = parent;
    }
    heap_[i] = e;
  }

  Entry pop() {
    const Entry top = heap_.front();
    const Entry last = heap_.back();
    heap_.pop_back();
    const size_t n = heap_.size();
    if (n == 0) return top;
    size_t i = 0;
    while (true) {
      const size_t first = 4 * i + 1;
      if (first >= n) break;
      size_t best = first;
      if (first + 4 <= n) {
        // All four children: pick the least without branches (conditional moves), since which
        // child wins is a coin toss the branch predictor would lose.
        Key best_key = heap_[first].key;
        for (size_t c = first + 1; c < first + 4; ++c) {
          const bool less = heap_[c].key < best_key;
          best = less ? c : best;
          best_key = less ? heap_[c].key : best_key;
        }
      } else {
        for (size_t c = first + 1; c < n; ++c)
          if (heap_[c].key < heap_[best].key) best = c;
      }
      if (!(heap_[best].key < last.key)) break;
      heap_[i] = heap_[best];
      i = best;
    }
    heap_[i] = last;
    return top;
  }

 private:
  std::vector<Entry> heap_;
};

}  // namespace navd::planning
