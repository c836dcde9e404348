#pragma once
// Cell buffers that lookup grids hand back when they go, for the next grid built on the same
// thread to take. SLAM builds a lookup grid for every scan and loop-closure candidate, and a wide
// scanner's neighbourhood makes one of megabytes: memory fresh from the system costs a page fault
// per 4 KiB on top of the zeroing every grid needs (an eighth of a whole-turn scanner's SLAM
// time), while a buffer kept costs only the zeroing.
#include <cstddef>
#include <vector>

namespace navd::mapping {

class RecycledCells {
 public:
  // `n` cells of 0, in the smallest buffer handed back on this thread that holds them (else the
  // roomiest, grown; else new memory).
  static std::vector<float> Take(size_t n);
  // Keeps `cells`' memory for a later Take on this thread: at most kKept buffers of at most
  // kMaxCells each, the roomiest.
  static void Give(std::vector<float>&& cells);

  static constexpr size_t kKept = 4;               // a loop closure's grids at three resolutions and the front end's
  static constexpr size_t kMaxCells = 16'000'000;  // 64 MB: a larger grid's memory goes back
};

}  // namespace navd::mapping
