#pragma once
// A 64-bit key for an integer grid cell, to sort or hash points by the cell they fall in: x in the
// high 32 bits, y's low 32 bits in the low ones. Distinct for cells within ±2³¹ of the origin, far
// beyond any map navd holds.
#include <cstdint>

namespace navd::mapping {

inline int64_t CellKey(int64_t x, int64_t y) {
  return static_cast<int64_t>((static_cast<uint64_t>(x) << 32) ^ static_cast<uint32_t>(y));
}

}  // namespace navd::mapping
