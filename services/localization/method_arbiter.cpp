#include "services/localization/method_arbiter.h"

#include <algorithm>
#include <cmath>

#include "services/common/error.h"

namespace navd::localization {
namespace {

// Scores closer than this are equal: sums like 1 + 0.4 * 5 + 0.2 * 5 + ... land a few ulps
// apart from the same value reached another way.
constexpr double kTie = 1e-9;

}  // namespace

MethodArbiter::MethodArbiter(MethodArbiterOptions options) : options_(options), rng_(options.seed) {
  if (options_.switch_after < 1) {
    throw Error(ErrorCode::kInvalidArgument, "switch_after: must be at least 1");
  }
}

std::vector<double> MethodArbiter::Suitability(const std::vector<MethodContext>& methods,
                                               const std::vector<double>& weights) {
  double sum = 0.0;
  for (size_t i = 0; i < weights.size(); ++i) {
    if (!std::isfinite(weights[i]) || weights[i] < 0) {
      throw Error(ErrorCode::kInvalidArgument, "weights[" + std::to_string(i) + "]: must be a non-negative number");
    }
    sum += weights[i];
  }
  if (std::abs(sum - 1.0) > 1e-6) {
    throw Error(ErrorCode::kInvalidArgument, "weights: must sum to 1 (they sum to " + std::to_string(sum) + ")");
  }
  std::vector<double> scores;
  scores.reserve(methods.size());
  for (const MethodContext& m : methods) {
    const std::string field = "methods['" + m.name + "']";
    if (m.gate != 0.0 && m.gate != 1.0) throw Error(ErrorCode::kInvalidArgument, field + ".gate: must be 0 or 1");
    if (m.criteria.size() != weights.size()) {
      throw Error(ErrorCode::kInvalidArgument, field + ".criteria: has " + std::to_string(m.criteria.size()) +
                                                   " values for " + std::to_string(weights.size()) + " weights");
    }
    double s = 1.0;
    for (size_t i = 0; i < weights.size(); ++i) {
      const double c = m.criteria[i];
      if (!(c >= 1.0 && c <= 5.0)) {
        throw Error(ErrorCode::kInvalidArgument, field + ".criteria[" + std::to_string(i) + "]: must lie in [1, 5]");
      }
      s += weights[i] * c;
    }
    scores.push_back(m.gate * s);
  }
  return scores;
}

size_t MethodArbiter::Winner(const std::vector<double>& scores) {
  const double best = *std::max_element(scores.begin(), scores.end());
  std::vector<size_t> tied;
  for (size_t i = 0; i < scores.size(); ++i) {
    if (best - scores[i] <= kTie) tied.push_back(i);
  }
  if (tied.size() == 1) return tied[0];
  if (active_ && std::find(tied.begin(), tied.end(), *active_) != tied.end()) return *active_;
  return tied[std::uniform_int_distribution<size_t>(0, tied.size() - 1)(rng_)];
}

size_t MethodArbiter::Update(const std::vector<MethodContext>& methods, const std::vector<double>& weights) {
  if (methods.empty()) throw Error(ErrorCode::kInvalidArgument, "methods: none to choose from");
  if (!scores_.empty() && scores_.size() != methods.size()) {
    throw Error(ErrorCode::kInvalidArgument, "methods: the set of methods changed between evaluations");
  }
  scores_ = Suitability(methods, weights);
  winner_ = Winner(scores_);
  if (!active_) {
    active_ = winner_;
  } else if (*winner_ == *active_) {
    candidate_.reset();
    candidate_wins_ = 0;
  } else {
    candidate_wins_ = candidate_ == winner_ ? candidate_wins_ + 1 : 1;
    candidate_ = winner_;
    if (candidate_wins_ >= options_.switch_after) {
      active_ = winner_;
      candidate_.reset();
      candidate_wins_ = 0;
    }
  }
  return *active_;
}

}  // namespace navd::localization
