#pragma once
// Gaussian samples by the ziggurat method (Marsaglia & Tsang 2000, in Doornik's 2005 form with
// 128 layers): most samples cost one 64-bit draw, a multiply and a compare, where
// std::normal_distribution pays a logarithm and a square root for every other sample. navsim draws
// one per laser beam, 6830 per simulated second, so this is what keeps noise cheap at 1000x real
// time. Deterministic for a given engine state, like the standard distributions.
#include <array>
#include <cstdint>
#include <random>

namespace navd {

class ZigguratNormal {
 public:
  ZigguratNormal(double mean = 0.0, double stddev = 1.0) : mean_(mean), stddev_(stddev) {}

  double operator()(std::mt19937_64& rng) const { return mean_ + stddev_ * Standard(rng); }
  // A sample of N(0, 1).
  static double Standard(std::mt19937_64& rng);

 private:
  double mean_, stddev_;
};

}  // namespace navd
