#include "services/planning/scenario_benchmark.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "services/common/error.h"

namespace navd::planning {
namespace {

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(std::ceil(q * v.size())) - (q > 0 ? 1 : 0));
  return v[i];
}

// The file prints lengths rounded to `decimals` digits; compare at that precision.
bool SameAsPrinted(double actual, double expected, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::abs(std::round(actual * scale) / scale - expected) < 1e-6 || std::abs(actual - expected) < 1e-6;
}

}  // namespace

std::string ScenarioReport::Summary() const {
  char buf[160];
  const char* verdict = objective == GlobalPlanner::Objective::kGridLength       ? "optimal"
                        : objective == GlobalPlanner::Objective::kAnyAngleLength ? "no longer than optimal"
                                                                                 : "found (not judged on length)";
  std::snprintf(buf, sizeof buf, "%s: %zu/%zu %s, median %.3f ms, p99 %.3f ms", planner.c_str(), passed, total, verdict,
                median_ms, p99_ms);
  return buf;
}

ScenarioReport RunScenarios(PlanningEngine& engine, const OccupancyGrid& grid,
                            const std::vector<MovingAiScenario>& scenarios, const std::string& planner,
                            const std::function<void(size_t, size_t)>& progress) {
  ScenarioReport report;
  report.total = scenarios.size();
  for (const auto& info : engine.Planners()) {
    if (info.name == (planner.empty() ? engine.options().default_planner : planner)) {
      report.planner = info.name;
      report.objective = info.objective;
    }
  }
  if (report.planner.empty()) engine.ComputePath({0, 0}, {0, 0}, planner, {});  // throws: unknown planner
  std::vector<double> times;
  for (size_t i = 0; i < scenarios.size(); ++i) {
    const auto& s = scenarios[i];
    ScenarioMismatch m{i, s.optimal_length, -1.0, ""};
    try {
      const PathPlan plan =
          engine.ComputePath(MovingAiCellCenter(grid, s.start_x, s.start_row),
                             MovingAiCellCenter(grid, s.goal_x, s.goal_row), report.planner, {{"smooth", 0.0}});
      times.push_back(plan.planning_time * 1e3);
      m.actual = plan.length;
      bool ok = true;  // kCost: finding a path is the test
      if (report.objective == GlobalPlanner::Objective::kGridLength) {
        ok = SameAsPrinted(plan.length, s.optimal_length, s.decimals);
      } else if (report.objective == GlobalPlanner::Objective::kAnyAngleLength) {
        ok = plan.length <= s.optimal_length + std::pow(10.0, -s.decimals);
      }
      if (ok)
        ++report.passed;
      else
        report.mismatches.push_back(m);
    } catch (const Error& e) {
      m.error = e.what();
      report.mismatches.push_back(m);
    }
    if (progress) progress(i + 1, scenarios.size());
  }
  report.median_ms = Percentile(times, 0.5);
  report.p99_ms = Percentile(times, 0.99);
  return report;
}

}  // namespace navd::planning
