// The chapter-10 method arbiter (Dynamic Selection of Methods): the book's Table 1 and its
// worked localisation example (areas a-d: DGPS, visual odometry, Kalman filter, odometry)
// reproduced number for number, the tie rule and the 10-in-a-row filter.
#include <gtest/gtest.h>

#include <set>

#include "services/common/error.h"
#include "services/localization/method_arbiter.h"

namespace navd::localization {
namespace {

TEST(MethodArbiter, TableOneGatesBeatTheBestWeightedMethod) {
  // Criteria C1, C2, C4 weighted 0.5, 0.25, 0.25; C3 and C5 critical (gate = C3 * C5).
  const std::vector<MethodContext> methods = {{"1", 0 * 1, {4, 3, 1}},
                                              {"2", 1 * 1, {1, 1, 3}},
                                              {"3", 1 * 1, {2, 2, 2}},
                                              {"4", 1 * 0, {5, 5, 1}},  // 5.0 were it not gated
                                              {"5", 0 * 0, {2, 2, 2}}};
  const std::vector<double> weights = {0.5, 0.25, 0.25};
  const auto s = MethodArbiter::Suitability(methods, weights);
  const std::vector<double> book = {0, 2.5, 3, 0, 0};
  for (size_t i = 0; i < s.size(); ++i) EXPECT_NEAR(s[i], book[i], 1e-12) << "method " << i + 1;
  MethodArbiter arbiter;
  EXPECT_EQ(arbiter.Update(methods, weights), 2u);  // "the selected method would be the number 3"
}

// Section 4: odometry O, DGPS G, Kalman K, visual odometry V; criteria in the order computing
// time, luminosity, fault tolerance, precision. CT and FT are fixed (CT 5/2/1/4, FT 2/4/5/3).
struct Area {
  const char* name;
  std::vector<double> weights;
  double dgps_gate;                // GPS signal: four satellites or more
  std::vector<double> luminosity;  // O, G, K, V
  std::vector<double> precision;
  std::vector<double> book_scores;
  size_t book_winner;
};

std::vector<MethodContext> Methods(const Area& a) {
  const char* names[] = {"odometry", "dgps", "kalman", "visual_odometry"};
  const double ct[] = {5, 2, 1, 4}, ft[] = {2, 4, 5, 3};
  std::vector<MethodContext> m;
  for (size_t i = 0; i < 4; ++i) {
    m.push_back({names[i], i == 1 ? a.dgps_gate : 1.0, {ct[i], a.luminosity[i], ft[i], a.precision[i]}});
  }
  return m;
}

const std::vector<Area>& BookAreas() {
  static const std::vector<Area> areas = {
      {"a: wide open space", {0.25, 0.25, 0.25, 0.25}, 1, {5, 5, 5, 5}, {2, 5, 3, 3}, {4.5, 5, 4.5, 4.75}, 1},
      {"b: narrow way under trees, faster", {0.4, 0.2, 0.2, 0.2}, 0, {5, 5, 5, 5}, {2, 2, 3, 4}, {4.8, 0, 4, 5}, 3},
      {"c: open space near buildings, slower",
       {0.1, 0.3, 0.3, 0.3},
       1,
       {5, 5, 5, 5},
       {2, 3, 3, 3},
       {4.2, 4.8, 5, 4.7},
       2},
      {"d: inside the library", {0.25, 0.25, 0.25, 0.25}, 0, {5, 5, 5, 4}, {3, 1, 3, 3}, {4.75, 0, 4.5, 4.5}, 0}};
  return areas;
}

TEST(MethodArbiter, BookLocalisationExampleAreasAToD) {
  for (const Area& a : BookAreas()) {
    const auto s = MethodArbiter::Suitability(Methods(a), a.weights);
    ASSERT_EQ(s.size(), 4u);
    for (size_t i = 0; i < 4; ++i) EXPECT_NEAR(s[i], a.book_scores[i], 1e-12) << a.name << ", method " << i;
    MethodArbiter fresh;
    EXPECT_EQ(fresh.Update(Methods(a), a.weights), a.book_winner) << a.name;
  }
}

TEST(MethodArbiter, WalkThroughTheAreasSwitchesOnTheTenthWinInARow) {
  // 2 s per area at the book's 0.2 s sampling and more: G, then V, K, O, each taking over on the
  // tenth consecutive win of the new winner.
  MethodArbiter arbiter;
  size_t expected = BookAreas()[0].book_winner;
  for (const Area& a : BookAreas()) {
    for (int cycle = 1; cycle <= 15; ++cycle) {
      const size_t active = arbiter.Update(Methods(a), a.weights);
      EXPECT_EQ(*arbiter.last_winner(), a.book_winner);
      if (cycle >= 10) expected = a.book_winner;
      EXPECT_EQ(active, expected) << a.name << ", cycle " << cycle;
    }
  }
  EXPECT_EQ(*arbiter.active(), 0u);  // odometry in the library
}

TEST(MethodArbiter, AlternatingWinnersNeverTakeOverAndTiesKeepTheCurrentMethod) {
  const std::vector<double> w = {1.0};
  MethodArbiter arbiter;
  arbiter.Update({{"a", 1, {5}}, {"b", 1, {1}}, {"c", 1, {1}}}, w);
  ASSERT_EQ(*arbiter.active(), 0u);
  // b and c win in turn, each never ten times in a row: a stays in charge.
  for (int i = 0; i < 40; ++i) {
    const bool b = i % 2 == 0;
    EXPECT_EQ(arbiter.Update({{"a", 1, {2}}, {"b", 1, {b ? 5.0 : 1.0}}, {"c", 1, {b ? 1.0 : 5.0}}}, w), 0u);
  }
  // a tied with the best: a stays, and the pending count of a challenger is dropped.
  for (int i = 0; i < 20; ++i) EXPECT_EQ(arbiter.Update({{"a", 1, {4}}, {"b", 1, {4}}, {"c", 1, {1}}}, w), 0u);
  EXPECT_EQ(*arbiter.last_winner(), 0u);
}

TEST(MethodArbiter, TiesWithoutTheCurrentMethodAreDrawnAtRandomReproducibly) {
  const std::vector<double> w = {1.0};
  const std::vector<MethodContext> tie = {{"a", 1, {1}}, {"b", 1, {5}}, {"c", 1, {5}}};
  std::set<size_t> drawn;
  for (uint64_t seed = 1; seed <= 40; ++seed) {
    MethodArbiter first({1, seed}), second({1, seed});
    const size_t x = first.Update(tie, w);
    EXPECT_EQ(second.Update(tie, w), x);  // the same seed draws the same
    EXPECT_NE(x, 0u);
    drawn.insert(x);
  }
  EXPECT_EQ(drawn, (std::set<size_t>{1, 2}));
}

TEST(MethodArbiter, BadContextNamesTheField) {
  const auto message = [](const std::vector<MethodContext>& m, const std::vector<double>& w) {
    try {
      MethodArbiter::Suitability(m, w);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message({{"a", 1, {3, 3}}}, {0.5, 0.6}).find("weights: must sum to 1"), std::string::npos);
  EXPECT_NE(message({{"a", 1, {3, 3}}}, {1.5, -0.5}).find("weights[1]"), std::string::npos);
  EXPECT_NE(message({{"amcl", 1, {3}}}, {0.5, 0.5}).find("methods['amcl'].criteria: has 1 values for 2 weights"),
            std::string::npos);
  EXPECT_NE(message({{"amcl", 1, {3, 6}}}, {0.5, 0.5}).find("methods['amcl'].criteria[1]: must lie in [1, 5]"),
            std::string::npos);
  EXPECT_NE(message({{"amcl", 0.5, {3, 3}}}, {0.5, 0.5}).find("methods['amcl'].gate"), std::string::npos);
  EXPECT_THROW(MethodArbiter({0, 1}), Error);
  MethodArbiter arbiter;
  EXPECT_THROW(arbiter.Update({}, {1.0}), Error);
}

}  // namespace
}  // namespace navd::localization
