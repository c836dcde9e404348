#include "services/mapping/recycled_cells.h"

#include <algorithm>
#include <iterator>
#include <utility>

namespace navd::mapping {
namespace {

std::vector<std::vector<float>>& Kept() {
  thread_local std::vector<std::vector<float>> kept;
  return kept;
}

bool Roomier(const std::vector<float>& a, const std::vector<float>& b) { return a.capacity() > b.capacity(); }

}  // namespace

std::vector<float> RecycledCells::Take(size_t n) {
  std::vector<std::vector<float>>& kept = Kept();
  std::vector<float> cells;
  if (!kept.empty()) {
    // Roomiest first: the last that holds n is the smallest that does.
    std::sort(kept.begin(), kept.end(), Roomier);
    auto chosen =
        std::find_if(kept.rbegin(), kept.rend(), [n](const std::vector<float>& b) { return b.capacity() >= n; });
    const auto at = chosen == kept.rend() ? kept.begin() : std::prev(chosen.base());
    cells = std::move(*at);
    kept.erase(at);
  }
  cells.assign(n, 0.0f);
  return cells;
}

void RecycledCells::Give(std::vector<float>&& cells) {
  if (cells.capacity() == 0 || cells.capacity() > kMaxCells) return;
  std::vector<std::vector<float>>& kept = Kept();
  kept.push_back(std::move(cells));
  if (kept.size() <= kKept) return;
  kept.erase(std::max_element(kept.begin(), kept.end(), Roomier));  // the smallest
}

}  // namespace navd::mapping
