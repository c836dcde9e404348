#pragma once
// Exact path costs on 8-connected grids: every length is a + b*sqrt(2) with integer a, b (a
// straight steps, b diagonal ones, and the octile heuristic has the same form). Comparing such
// values exactly keeps incremental searches such as D* Lite free of floating-point ties, where
// nodes on equally long paths compare unequal in the last bit and the search stops too early.
#include <cmath>
#include <cstdint>
#include <limits>

namespace navd::planning {

struct OctileCost {
  int64_t a = 0;  // straight steps
  int64_t b = 0;  // diagonal steps

  static OctileCost Infinite() { return {std::numeric_limits<int64_t>::max() / 4, 0}; }
  bool infinite() const { return a >= std::numeric_limits<int64_t>::max() / 8; }
  double value() const { return infinite() ? std::numeric_limits<double>::infinity() : a + b * M_SQRT2; }

  OctileCost operator+(const OctileCost& o) const {
    if (infinite() || o.infinite()) return Infinite();
    return {a + o.a, b + o.b};
  }
  // Octile distance between cells dx, dy apart.
  static OctileCost Distance(int64_t dx, int64_t dy) {
    dx = dx < 0 ? -dx : dx;
    dy = dy < 0 ? -dy : dy;
    const int64_t lo = dx < dy ? dx : dy, hi = dx < dy ? dy : dx;
    return {hi - lo, lo};
  }

  // Sign of (a1 - a2) + (b1 - b2) * sqrt(2), exactly.
  static int Compare(const OctileCost& x, const OctileCost& y) {
    if (x.infinite() || y.infinite()) return x.infinite() == y.infinite() ? 0 : (x.infinite() ? 1 : -1);
    const int64_t da = x.a - y.a, db = x.b - y.b;
    // Fast path: far from zero, the double value has the right sign (|da|, |db| < 2^40 here).
    const double approx = static_cast<double>(da) + static_cast<double>(db) * M_SQRT2;
    if (approx > 1e-3) return 1;
    if (approx < -1e-3) return -1;
    if (da >= 0 && db >= 0) return (da == 0 && db == 0) ? 0 : 1;
    if (da <= 0 && db <= 0) return -1;
    // Opposite signs: compare da^2 with 2 db^2 (magnitudes), the larger term decides the sign.
    const __int128 l = static_cast<__int128>(da) * da, r = 2 * static_cast<__int128>(db) * db;
    if (l == r) return 0;  // cannot happen for integers (sqrt 2 is irrational) unless both are 0
    return (l > r) == (da > 0) ? 1 : -1;
  }
  bool operator<(const OctileCost& o) const { return Compare(*this, o) < 0; }
  bool operator==(const OctileCost& o) const { return Compare(*this, o) == 0; }
  bool operator!=(const OctileCost& o) const { return !(*this == o); }
  bool operator<=(const OctileCost& o) const { return Compare(*this, o) <= 0; }
};

inline OctileCost Min(const OctileCost& x, const OctileCost& y) { return y < x ? y : x; }

}  // namespace navd::planning
