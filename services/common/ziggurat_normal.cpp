#include "services/common/ziggurat_normal.h"

#include <cmath>

namespace navd {
namespace {

constexpr int kLayers = 128;
// Start of the tail and area of each layer for 128 layers (Marsaglia & Tsang).
constexpr double kTailStart = 3.442619855899;
constexpr double kLayerArea = 9.91256303526217e-3;
constexpr double kTwoPowMinus53 = 1.0 / 9007199254740992.0;

struct Layers {
  std::array<double, kLayers + 1> x{};  // right edges; x[0] is the base layer's equivalent width
  std::array<double, kLayers> ratio{};  // x[i + 1] / x[i]: the share of layer i under the curve
  Layers() {
    double f = std::exp(-0.5 * kTailStart * kTailStart);
    x[0] = kLayerArea / f;
    x[1] = kTailStart;
    x[kLayers] = 0.0;
    for (int i = 2; i < kLayers; ++i) {
      x[i] = std::sqrt(-2.0 * std::log(kLayerArea / x[i - 1] + f));
      f = std::exp(-0.5 * x[i] * x[i]);
    }
    for (int i = 0; i < kLayers; ++i) ratio[i] = x[i + 1] / x[i];
  }
};

const Layers& TheLayers() {
  static const Layers layers;
  return layers;
}

// Uniform in (0, 1), never 0, so its logarithm is finite.
double OpenUniform(std::mt19937_64& rng) { return (static_cast<double>(rng() >> 11) + 0.5) * kTwoPowMinus53; }

}  // namespace

double ZigguratNormal::Standard(std::mt19937_64& rng) {
  const Layers& z = TheLayers();
  while (true) {
    const uint64_t bits = rng();
    // Top 53 bits: a uniform in [-1, 1); lowest 7 bits: the layer.
    const double u = 2.0 * (static_cast<double>(bits >> 11) * kTwoPowMinus53) - 1.0;
    const int i = static_cast<int>(bits & (kLayers - 1));
    if (std::abs(u) < z.ratio[i]) return u * z.x[i];  // inside the layer's rectangle: ~99% of draws
    if (i == 0) {
      // Beyond the last layer: Marsaglia's exact tail sampler.
      double tx, ty;
      do {
        tx = std::log(OpenUniform(rng)) / kTailStart;
        ty = std::log(OpenUniform(rng));
      } while (-2.0 * ty < tx * tx);
      return u < 0 ? tx - kTailStart : kTailStart - tx;
    }
    // In the wedge between the rectangle and the curve: accept under the density.
    const double x = u * z.x[i];
    const double f0 = std::exp(-0.5 * (z.x[i] * z.x[i] - x * x));
    const double f1 = std::exp(-0.5 * (z.x[i + 1] * z.x[i + 1] - x * x));
    if (f1 + OpenUniform(rng) * (f0 - f1) < 1.0) return x;
  }
}

}  // namespace navd
