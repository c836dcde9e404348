// The delivery scheduler: its rules always hold, it finds the shortest round on small instances
// (checked against every order), beats the order given, and names the stop no path reaches.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "services/common/error.h"
#include "services/navigation/delivery_scheduler.h"

namespace navd::navigation {
namespace {

double Euclid(const Point2& a, const Point2& b) { return Distance(a, b); }

std::vector<DeliveryTask> RandomTasks(std::mt19937& rng, int n, int priorities) {
  std::uniform_real_distribution<double> u(0.0, 10.0);
  std::uniform_int_distribution<int> p(0, priorities - 1);
  std::vector<DeliveryTask> tasks;
  tasks.reserve(n);
  for (int i = 0; i < n; ++i) tasks.push_back({"t" + std::to_string(i), {u(rng), u(rng)}, {u(rng), u(rng)}, p(rng)});
  return tasks;
}

// The rules, checked on a schedule: every stop once, pickups first, load, priorities.
void ExpectRulesHold(const DeliverySchedule& s, const std::vector<DeliveryTask>& tasks, size_t capacity) {
  ASSERT_EQ(s.stops.size(), 2 * tasks.size());
  std::vector<int> picked(tasks.size(), 0), dropped(tasks.size(), 0);
  size_t load = 0;
  int last_priority = 1 << 30;
  for (const DeliveryStop& stop : s.stops) {
    if (stop.pickup) {
      ++picked[stop.task];
      ++load;
      if (capacity > 0) {
        EXPECT_LE(load, capacity);
      }
    } else {
      EXPECT_EQ(picked[stop.task], 1) << "dropoff before pickup";
      ++dropped[stop.task];
      --load;
      EXPECT_LE(tasks[stop.task].priority, last_priority) << "a lower priority delivered first";
      last_priority = tasks[stop.task].priority;
    }
  }
  for (size_t t = 0; t < tasks.size(); ++t) EXPECT_EQ(picked[t] + dropped[t], 2);
}

// The shortest feasible round, by trying every order of the stops.
double BruteForce(const Point2& start, const std::vector<DeliveryTask>& tasks, const DeliveryScheduleOptions& o) {
  std::vector<size_t> order(2 * tasks.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  double best = 1e18;
  do {
    std::vector<bool> picked(tasks.size(), false);
    size_t load = 0;
    int last = 1 << 30;
    bool ok = true;
    double length = 0.0;
    Point2 at = start;
    for (size_t s : order) {
      const DeliveryTask& t = tasks[s / 2];
      if (s % 2 == 0) {
        picked[s / 2] = true;
        ok &= o.capacity == 0 || ++load <= o.capacity;
        length += Distance(at, t.pickup);
        at = t.pickup;
      } else {
        ok &= picked[s / 2] && t.priority <= last;
        last = t.priority;
        --load;
        length += Distance(at, t.dropoff);
        at = t.dropoff;
      }
      if (!ok) break;
    }
    if (o.return_to_start) length += Distance(at, start);
    if (ok) best = std::min(best, length);
  } while (std::next_permutation(order.begin(), order.end()));
  return best;
}

// Against every order: `exact_up_to` 7 (the default) must be optimal; 0 measures the heuristic.
struct Quality {
  int optimal = 0, instances = 0;
  double worst = 1.0;
};
Quality CompareWithEveryOrder(size_t exact_up_to) {
  std::mt19937 rng(5);
  Quality q;
  for (int i = 0; i < 60; ++i) {
    const auto tasks = RandomTasks(rng, 4, i % 3 == 0 ? 2 : 1);
    DeliveryScheduleOptions o;
    o.exact_up_to = exact_up_to;
    o.capacity = static_cast<size_t>(i % 4);  // 0 (no limit), 1, 2, 3
    o.return_to_start = i % 2 == 0;
    const DeliverySchedule s = ScheduleDeliveries({5.0, 5.0}, tasks, o, Euclid);
    ExpectRulesHold(s, tasks, o.capacity);
    double sum = 0.0;
    for (const DeliveryStop& stop : s.stops) sum += stop.leg_length;
    if (!o.return_to_start) {
      EXPECT_NEAR(sum, s.length, 1e-9);
    }
    const double best = BruteForce({5.0, 5.0}, tasks, o);
    EXPECT_GE(s.length, best - 1e-9);
    q.worst = std::max(q.worst, s.length / best);
    q.optimal += s.length <= best + 1e-9;
    ++q.instances;
  }
  return q;
}

TEST(DeliveryScheduler, KeepsItsRulesAndFindsTheShortestRoundOnSmallInstances) {
  const Quality exact = CompareWithEveryOrder(7);
  EXPECT_EQ(exact.optimal, exact.instances);
  const Quality heuristic = CompareWithEveryOrder(0);
  std::printf("heuristic: optimal in %d of %d instances, worst %.3f x the optimum\n", heuristic.optimal,
              heuristic.instances, heuristic.worst);
  EXPECT_GE(heuristic.optimal, heuristic.instances * 9 / 10);
  EXPECT_LT(heuristic.worst, 1.10);
}

TEST(DeliveryScheduler, CombinesTripsTheGivenOrderDrivesSeparately) {
  // Two parcels from the same shelf to the same bay, the shelf and the bay 8 m apart: carrying
  // both at once drives 8 + 8 m less than one at a time; with capacity 1 it cannot.
  const std::vector<DeliveryTask> tasks = {{"a", {8, 0}, {0, 8}, 0}, {"b", {8, 0.2}, {0, 8.2}, 0}};
  DeliveryScheduleOptions o;
  const DeliverySchedule both = ScheduleDeliveries({0, 0}, tasks, o, Euclid);
  EXPECT_TRUE(both.stops[0].pickup && both.stops[1].pickup);
  EXPECT_LT(both.length, both.given_order_length - 10.0);
  o.capacity = 1;
  const DeliverySchedule one = ScheduleDeliveries({0, 0}, tasks, o, Euclid);
  EXPECT_TRUE(one.stops[0].pickup && !one.stops[1].pickup);
  // A higher priority goes first even when it is the longer way.
  const std::vector<DeliveryTask> urgent = {{"near", {1, 0}, {2, 0}, 0}, {"far", {9, 0}, {9, 9}, 5}};
  const DeliverySchedule u = ScheduleDeliveries({0, 0}, urgent, {}, Euclid);
  const auto first_drop = std::find_if(u.stops.begin(), u.stops.end(), [](const DeliveryStop& s) { return !s.pickup; });
  EXPECT_EQ(first_drop->task, 1u);
}

TEST(DeliveryScheduler, NamesTheStopNoPathReaches) {
  const std::vector<DeliveryTask> tasks = {{"a", {1, 0}, {2, 0}, 0}, {"b", {3, 0}, {50, 0}, 0}};
  // Nothing beyond x = 10 can be reached.
  const PathLength walled = [](const Point2& a, const Point2& b) {
    return (a.x() > 10) != (b.x() > 10) ? std::numeric_limits<double>::infinity() : Distance(a, b);
  };
  try {
    ScheduleDeliveries({0, 0}, tasks, {}, walled);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNotFound);
    EXPECT_NE(std::string(e.what()).find("tasks[1].dropoff"), std::string::npos) << e.what();
  }
  try {
    ScheduleDeliveries({0, 0}, {{"nan", {NAN, 0}, {1, 1}, 0}}, {}, Euclid);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(e.what()).find("tasks[0].pickup"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace navd::navigation
