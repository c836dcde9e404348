#pragma once
// Dynamic Selection of Methods (book chapter 10, Guirado et al.): choosing at run time which
// localisation method answers, from the context. Each method gets a suitability
//   S_M = g_M * (1 + sum_i W_i * C_i,M)                                   (Eqs. 1-2)
// where g_M is the product of its critical criteria (0 when the method cannot work now, e.g.
// DGPS with fewer than four satellites, a scan matcher without a laser) and C_i,M are its
// non-critical criteria, 1 (poor) to 5 (best), weighted by W_i (summing to 1; the weights follow
// the situation: a hurried robot weighs computing time, a narrow passage precision).
// The best method wins; on a tie the current method stays if it is among the best, otherwise one
// of them is drawn at random (seeded). A filter against sensor noise (the book: "a decision will
// not be taken until ... 10 consecutive times") switches only after the same new winner has won
// `switch_after` evaluations in a row.
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace navd::localization {

// One method's criteria at one evaluation.
struct MethodContext {
  std::string name;
  double gate = 1.0;             // product of the critical criteria: 0 or 1
  std::vector<double> criteria;  // non-critical, 1..5, in the order of the weights
};

struct MethodArbiterOptions {
  int switch_after = 10;  // consecutive wins a new method needs (1: no filter)
  uint64_t seed = 1;      // for the random choice among tied methods
};

class MethodArbiter {
 public:
  explicit MethodArbiter(MethodArbiterOptions options = {});

  // Eq. 2 for every method. Throws navd::Error(kInvalidArgument) naming the field: weights that
  // are negative or do not sum to 1 (within 1e-6), a criterion count that differs from the
  // weights', gates other than 0 or 1, criteria outside [1, 5] or not finite.
  static std::vector<double> Suitability(const std::vector<MethodContext>& methods, const std::vector<double>& weights);

  // One evaluation: scores the methods, applies the tie rule and the filter, and returns the
  // index of the method in charge afterwards. The first evaluation selects at once. The methods
  // must be the same, in the same order, at every evaluation.
  size_t Update(const std::vector<MethodContext>& methods, const std::vector<double>& weights);

  // The method in charge (empty before the first Update), and this evaluation's winner.
  std::optional<size_t> active() const { return active_; }
  std::optional<size_t> last_winner() const { return winner_; }
  const std::vector<double>& last_scores() const { return scores_; }

 private:
  size_t Winner(const std::vector<double>& scores);

  MethodArbiterOptions options_;
  std::mt19937_64 rng_;
  std::optional<size_t> active_, winner_, candidate_;
  int candidate_wins_ = 0;
  std::vector<double> scores_;
};

}  // namespace navd::localization
