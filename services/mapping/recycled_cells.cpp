#include "services/mapping/recycled_cells.h"

#include <algorithm>
#include <utility>

namespace navd::mapping {
namespace {

std::vector<std::vector<float>>& Kept() {
  thread_local std::vector<std::vector<float>> kept;
  return kept;
}

bool Smaller(const std::vector<float>& a, const std::vector<float>& b) { return a.capacity() < b.capacity(); }

}  // namespace

std::vector<float> RecycledCells::Take(size_t n) {
  std::vector<std::vector<float>>& kept = Kept();
  std::vector<float> cells;
  if (!kept.empty()) {
    // The smallest that holds n, else the roomiest.
    auto chosen = std::max_element(kept.begin(), kept.end(), Smaller);
    for (auto it = kept.begin(); it != kept.end(); ++it)
      if (it->capacity() >= n && it->capacity() < chosen->capacity()) chosen = it;
    cells = std::move(*chosen);
    kept.erase(chosen);
  }
  cells.assign(n, 0.0f);
  return cells;
}

void RecycledCells::Give(std::vector<float>&& cells) {
  if (cells.capacity() == 0 || cells.capacity() > kMaxCells) return;
  std::vector<std::vector<float>>& kept = Kept();
  kept.push_back(std::move(cells));
  if (kept.size() > kKept) kept.erase(std::min_element(kept.begin(), kept.end(), Smaller));
}

}  // namespace navd::mapping
