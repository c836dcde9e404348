#include "services/navigation/delivery_scheduler.h"

#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include "services/common/error.h"

namespace navd::navigation {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Stops are numbered 2 i (task i's pickup) and 2 i + 1 (its dropoff); point 0 of the distance
// matrix is the start, stop s is point s + 1.
class Round {
 public:
  Round(const std::vector<DeliveryTask>& tasks, const DeliveryScheduleOptions& options,
        std::vector<std::vector<double>> d)
      : tasks_(tasks), options_(options), d_(std::move(d)) {}

  double Length(const std::vector<size_t>& order) const {
    double total = 0.0;
    size_t at = 0;
    for (size_t s : order) {
      total += d_[at][s + 1];
      at = s + 1;
    }
    if (options_.return_to_start && !order.empty()) total += d_[at][0];
    return total;
  }

  // Pickups before dropoffs, the load within capacity, dropoffs by priority (highest first).
  bool Feasible(const std::vector<size_t>& order) const {
    std::vector<bool> picked(tasks_.size(), false);
    size_t load = 0;
    int last_priority = std::numeric_limits<int>::max();
    for (size_t s : order) {
      const size_t task = s / 2;
      if (s % 2 == 0) {
        picked[task] = true;
        if (options_.capacity > 0 && ++load > options_.capacity) return false;
      } else {
        if (!picked[task]) return false;
        if (tasks_[task].priority > last_priority) return false;
        last_priority = tasks_[task].priority;
        --load;
      }
    }
    return true;
  }

  // Cheapest feasible insertion of task t's pickup and dropoff into `order`; false when none is.
  bool Insert(std::vector<size_t>& order, size_t t) const {
    double best = kInf;
    std::vector<size_t> best_order;
    for (size_t i = 0; i <= order.size(); ++i) {
      for (size_t j = i + 1; j <= order.size() + 1; ++j) {
        std::vector<size_t> candidate = order;
        candidate.insert(candidate.begin() + i, 2 * t);
        candidate.insert(candidate.begin() + j, 2 * t + 1);
        if (!Feasible(candidate)) continue;
        const double length = Length(candidate);
        if (length < best) {
          best = length;
          best_order = std::move(candidate);
        }
      }
    }
    if (best_order.empty()) return false;
    order = std::move(best_order);
    return true;
  }

  // Applies the first shortening move found, of: one stop moved, a task's pair moved together,
  // two stops swapped. Returns whether one was.
  bool Improve(std::vector<size_t>& order) const {
    const double current = Length(order);
    auto try_order = [&](std::vector<size_t>&& candidate) {
      if (Feasible(candidate) && Length(candidate) < current - 1e-9) {
        order = std::move(candidate);
        return true;
      }
      return false;
    };
    const size_t n = order.size();
    for (size_t i = 0; i < n; ++i) {
      for (size_t j = 0; j < n; ++j) {
        if (i == j) continue;
        std::vector<size_t> moved = order;
        const size_t s = moved[i];
        moved.erase(moved.begin() + i);
        moved.insert(moved.begin() + j, s);
        if (try_order(std::move(moved))) return true;
        if (j > i) {
          std::vector<size_t> swapped = order;
          std::swap(swapped[i], swapped[j]);
          if (try_order(std::move(swapped))) return true;
        }
      }
    }
    for (size_t t = 0; t < tasks_.size(); ++t) {
      std::vector<size_t> without;
      for (size_t s : order)
        if (s / 2 != t) without.push_back(s);
      if (Insert(without, t) && Length(without) < current - 1e-9) {
        order = std::move(without);
        return true;
      }
    }
    return false;
  }

  // The shortest feasible round, by dynamic programming over (stops done, last stop). A set fixes
  // the load (pickups less dropoffs) and whether a dropoff may come next (every task of higher
  // priority already delivered), so the rules are checked on sets, not orders.
  std::vector<size_t> Exact() const {
    const size_t m = 2 * tasks_.size();
    const size_t sets = size_t{1} << m;
    std::vector<double> cost(sets * m, kInf);
    std::vector<uint8_t> from(sets * m, 0);
    auto allowed = [&](size_t set, size_t s) {
      if (set & (size_t{1} << s)) return false;
      const size_t t = s / 2;
      if (s % 2 == 0) {
        size_t load = 0;
        for (size_t k = 0; k < m; ++k)
          if (set & (size_t{1} << k)) load += k % 2 == 0 ? 1 : -1;
        return options_.capacity == 0 || load + 1 <= options_.capacity;
      }
      if (!(set & (size_t{1} << (2 * t)))) return false;
      for (size_t u = 0; u < tasks_.size(); ++u)
        if (tasks_[u].priority > tasks_[t].priority && !(set & (size_t{1} << (2 * u + 1)))) return false;
      return true;
    };
    for (size_t s = 0; s < m; ++s)
      if (allowed(0, s)) cost[(size_t{1} << s) * m + s] = d_[0][s + 1];
    for (size_t set = 1; set < sets; ++set) {
      for (size_t last = 0; last < m; ++last) {
        const double c = cost[set * m + last];
        if (c == kInf) continue;
        for (size_t s = 0; s < m; ++s) {
          if (!allowed(set, s)) continue;
          const size_t next = set | (size_t{1} << s);
          const double nc = c + d_[last + 1][s + 1];
          if (nc < cost[next * m + s]) {
            cost[next * m + s] = nc;
            from[next * m + s] = static_cast<uint8_t>(last);
          }
        }
      }
    }
    const size_t all = sets - 1;
    double best = kInf;
    size_t last = 0;
    for (size_t s = 0; s < m; ++s) {
      const double c = cost[all * m + s] + (options_.return_to_start ? d_[s + 1][0] : 0.0);
      if (c < best) {
        best = c;
        last = s;
      }
    }
    if (best == kInf) return {};
    std::vector<size_t> order;
    for (size_t set = all; set != 0;) {
      order.push_back(last);
      const size_t prev = from[set * m + last];
      set &= ~(size_t{1} << last);
      last = prev;
    }
    std::reverse(order.begin(), order.end());
    return order;
  }

 private:
  const std::vector<DeliveryTask>& tasks_;
  const DeliveryScheduleOptions& options_;
  std::vector<std::vector<double>> d_;
};

// Insertion, highest priority first (ties in the order given, then shuffled, seeded), each
// order improved by local search; the shortest of restarts + 1 attempts.
std::vector<size_t> InsertionOrder(const Round& round, const std::vector<DeliveryTask>& tasks,
                                   const DeliveryScheduleOptions& options) {
  std::vector<size_t> insertion(tasks.size());
  std::iota(insertion.begin(), insertion.end(), size_t{0});
  std::mt19937 rng(17);
  double best = kInf;
  std::vector<size_t> order;
  for (int attempt = 0; attempt <= options.restarts; ++attempt) {
    if (attempt > 0) std::shuffle(insertion.begin(), insertion.end(), rng);
    std::stable_sort(insertion.begin(), insertion.end(),
                     [&](size_t a, size_t b) { return tasks[a].priority > tasks[b].priority; });
    std::vector<size_t> candidate;
    for (size_t t : insertion) {
      // Always possible: the pair appended at the end keeps every rule.
      round.Insert(candidate, t);
    }
    while (round.Improve(candidate)) {
    }
    if (const double length = round.Length(candidate); length < best - 1e-9) {
      best = length;
      order = std::move(candidate);
    }
  }
  return order;
}

}  // namespace

DeliverySchedule ScheduleDeliveries(const Point2& start, const std::vector<DeliveryTask>& tasks,
                                    const DeliveryScheduleOptions& options, const PathLength& length) {
  std::vector<Point2> points{start};
  for (size_t i = 0; i < tasks.size(); ++i) {
    const std::string field = "tasks[" + std::to_string(i) + "]";
    if (!tasks[i].pickup.allFinite()) throw Error(ErrorCode::kInvalidArgument, field + ".pickup is not a finite point");
    if (!tasks[i].dropoff.allFinite()) {
      throw Error(ErrorCode::kInvalidArgument, field + ".dropoff is not a finite point");
    }
    points.push_back(tasks[i].pickup);
    points.push_back(tasks[i].dropoff);
  }
  auto stop_name = [&](size_t point) {
    const size_t s = point - 1;
    return "tasks[" + std::to_string(s / 2) + "]." + (s % 2 == 0 ? "pickup" : "dropoff") + " " +
           FormatPoint(points[point]);
  };
  const size_t n = points.size();
  std::vector<std::vector<double>> d(n, std::vector<double>(n, 0.0));
  for (size_t a = 0; a < n; ++a) {
    for (size_t b = a + 1; b < n; ++b) {
      d[a][b] = d[b][a] = length(points[a], points[b]);
      if (!std::isfinite(d[a][b])) {
        // From the start: that stop is unreachable; between stops: the later one is.
        throw Error(ErrorCode::kNotFound, "no path from " + (a == 0 ? std::string("the robot") : stop_name(a)) +
                                              " to " + (b == 0 ? std::string("the robot's start") : stop_name(b)));
      }
    }
  }
  const Round round(tasks, options, d);

  // The order given: each task picked up and dropped off in turn.
  std::vector<size_t> given;
  for (size_t t = 0; t < tasks.size(); ++t) {
    given.push_back(2 * t);
    given.push_back(2 * t + 1);
  }

  const std::vector<size_t> order =
      tasks.size() <= options.exact_up_to ? round.Exact() : InsertionOrder(round, tasks, options);

  DeliverySchedule schedule;
  size_t at = 0;
  for (size_t s : order) {
    schedule.stops.push_back({s / 2, s % 2 == 0, points[s + 1], d[at][s + 1]});
    at = s + 1;
  }
  schedule.length = round.Length(order);
  schedule.given_order_length = round.Length(given);
  return schedule;
}

}  // namespace navd::navigation
