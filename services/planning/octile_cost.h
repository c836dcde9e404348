#pragma once
// Exact path costs on 8-connected grids. Every length is a + b*sqrt(2) with integer a, b (a
// straight steps, b diagonal ones, and the octile heuristic has the same form). Incremental
// searches such as D* Lite need these compared exactly: with doubles, nodes on equally long paths
// compare unequal in the last bit and the search stops too early.
//
// The value is held as one integer, a*S + b*D with S = 2^36 and D = round(sqrt(2) * S), so sums
// and comparisons are single integer operations. That order is the true order of a + b*sqrt(2)
// whenever |b| < ~300,000: the rounding error |b| * 0.234 / S stays below the smallest non-zero
// gap |a + b*sqrt(2)| >= 1 / (2.9 |b|) (sqrt 2's continued fraction), and D is odd, so a*S + b*D
// is zero only for a = b = 0. Finite costs go up to kMaxCells cells (searches check their grid).
#include <cmath>
#include <cstdint>
#include <limits>

namespace navd::planning {

class OctileCost {
 public:
  static constexpr int64_t kStraight = int64_t{1} << 36;
  static constexpr int64_t kDiagonal = 97184015999;  // round(sqrt(2) * 2^36), odd
  // The longest cost (in cells) that stays exact and finite, with room for D* Lite's key sums.
  static constexpr int64_t kMaxCells = (std::numeric_limits<int64_t>::max() / 4) / kStraight / 4;

  constexpr OctileCost() = default;
  static constexpr OctileCost Steps(int64_t straight, int64_t diagonal) {
    return OctileCost(straight * kStraight + diagonal * kDiagonal);
  }
  static constexpr OctileCost Infinite() { return OctileCost(kInfinite); }
  // Octile distance between cells dx, dy apart.
  static constexpr OctileCost Distance(int64_t dx, int64_t dy) {
    dx = dx < 0 ? -dx : dx;
    dy = dy < 0 ? -dy : dy;
    return dx < dy ? Steps(dy - dx, dx) : Steps(dx - dy, dy);
  }

  constexpr bool infinite() const { return v_ >= kInfinite; }
  // In cells; within 1e-12 relative of a + b*sqrt(2).
  double value() const {
    return infinite() ? std::numeric_limits<double>::infinity()
                      : static_cast<double>(v_) / static_cast<double>(kStraight);
  }

  constexpr OctileCost operator+(const OctileCost& o) const {
    return infinite() || o.infinite() ? Infinite() : OctileCost(v_ + o.v_);
  }
  constexpr bool operator<(const OctileCost& o) const { return v_ < o.v_; }
  constexpr bool operator==(const OctileCost& o) const { return v_ == o.v_; }
  constexpr bool operator!=(const OctileCost& o) const { return v_ != o.v_; }
  constexpr bool operator<=(const OctileCost& o) const { return v_ <= o.v_; }

 private:
  static constexpr int64_t kInfinite = std::numeric_limits<int64_t>::max() / 4;
  explicit constexpr OctileCost(int64_t v) : v_(v) {}
  int64_t v_ = 0;
};

inline constexpr OctileCost Min(const OctileCost& x, const OctileCost& y) { return y < x ? y : x; }

}  // namespace navd::planning
