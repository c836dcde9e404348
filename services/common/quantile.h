#pragma once
// The q-quantile of samples by nearest rank (the sample at rank floor(q x n), q = 1 the largest):
// what a median or a 95th percentile in navd's reports and estimates means. Samples are taken by
// value and partially reordered; 0 without samples.
#include <algorithm>
#include <cstddef>
#include <vector>

namespace navd {

template <typename T>
T Quantile(std::vector<T> samples, double q) {
  if (samples.empty()) return T{};
  const size_t k = std::min(samples.size() - 1, static_cast<size_t>(q * static_cast<double>(samples.size())));
  std::nth_element(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(k), samples.end());
  return samples[k];
}

}  // namespace navd
