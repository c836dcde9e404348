#include "services/navigation/utility_decision_maker.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "services/common/error.h"
#include "services/common/text_file.h"
#include "services/common/yaml_document.h"
#include "services/common/yaml_fields.h"

namespace navd::navigation {

UtilityDecisionMaker::UtilityDecisionMaker(UtilityBrainOptions options) : options_(std::move(options)) {
  const auto fail = [](const std::string& what) { throw Error(ErrorCode::kInvalidArgument, "brain: " + what); };
  std::set<std::string> names;
  for (const std::string& v : options_.state_variables) {
    if (!names.insert("z:" + v).second) fail("state variable '" + v + "' is listed twice");
  }
  bool any_motor = false;
  for (const UtilityProcessOptions& p : options_.processes) {
    if (p.name.empty()) fail("a process has no name");
    if (!names.insert(p.name).second) fail("process '" + p.name + "' is defined twice");
    if (!(p.tau > 0.0) || !std::isfinite(p.tau)) fail("process '" + p.name + "': tau must be a positive number");
    if (!(p.gamma_tau > 0.0) || !std::isfinite(p.gamma_tau)) {
      fail("process '" + p.name + "': gamma_tau must be a positive number");
    }
    if (!(p.c > 0.0) || !std::isfinite(p.c)) fail("process '" + p.name + "': c must be a positive number");
    if (!std::isfinite(p.b) || !std::isfinite(p.gamma_on_activation)) {
      fail("process '" + p.name + "': b and gamma_on_activation must be finite");
    }
    std::vector<std::pair<size_t, double>> w;
    for (const auto& [var, weight] : p.a) {
      size_t k = 0;
      while (k < options_.state_variables.size() && options_.state_variables[k] != var) ++k;
      if (k == options_.state_variables.size()) {
        fail("process '" + p.name + "': weight on unknown state variable '" + var + "'");
      }
      if (!std::isfinite(weight)) fail("process '" + p.name + "': weight on '" + var + "' is not finite");
      w.emplace_back(k, weight);
    }
    weights_.push_back(std::move(w));
    any_motor = any_motor || p.kind == ProcessKind::kMotor;
  }
  if (!any_motor) fail("no motor behaviour: exactly one must always be active");
  const size_t n = options_.processes.size();
  utility_.assign(n, options_.initial_utility);
  gamma_.assign(n, 0.0);
  active_.assign(n, false);
  was_active_.assign(n, false);
  Decide();
  was_active_ = active_;
}

void UtilityDecisionMaker::Update(double dt, const std::vector<double>& z) {
  if (z.size() != options_.state_variables.size()) {
    throw Error(ErrorCode::kInvalidArgument, "brain: " + std::to_string(z.size()) + " state values for " +
                                                 std::to_string(options_.state_variables.size()) + " variables");
  }
  if (!(dt > 0.0)) return;
  for (size_t i = 0; i < size(); ++i) {
    const UtilityProcessOptions& p = options_.processes[i];
    double x = p.b + gamma_[i];
    for (const auto& [k, a] : weights_[i]) x += a * z[k];
    const double target = std::tanh(p.c * x);
    // Exact solution of the linear ODE over the step with the input held.
    utility_[i] = target + (utility_[i] - target) * std::exp(-dt / p.tau);
    gamma_[i] *= std::exp(-dt / p.gamma_tau);
  }
  was_active_ = active_;
  Decide();
  for (size_t i = 0; i < size(); ++i) {
    if (activated(i) && options_.processes[i].gamma_on_activation != 0.0) {
      gamma_[i] = options_.processes[i].gamma_on_activation;
    }
  }
}

void UtilityDecisionMaker::Decide() {
  long best = -1;
  for (size_t i = 0; i < size(); ++i) {
    if (options_.processes[i].kind == ProcessKind::kCognitive) {
      active_[i] = utility_[i] > 0.0;
    } else if (best < 0 || utility_[i] > utility_[best]) {
      best = static_cast<long>(i);
    }
  }
  for (size_t i = 0; i < size(); ++i) {
    if (options_.processes[i].kind == ProcessKind::kMotor) active_[i] = static_cast<long>(i) == best;
  }
  active_motor_ = static_cast<size_t>(best);
}

void UtilityDecisionMaker::SetGamma(size_t process, double gamma) { gamma_.at(process) = gamma; }

long UtilityDecisionMaker::FindProcess(const std::string& name) const {
  for (size_t i = 0; i < size(); ++i)
    if (options_.processes[i].name == name) return static_cast<long>(i);
  return -1;
}

size_t UtilityDecisionMaker::ProcessIndex(const std::string& name) const {
  const long i = FindProcess(name);
  if (i < 0) throw Error(ErrorCode::kInvalidArgument, "brain: no process named '" + name + "'");
  return static_cast<size_t>(i);
}

size_t UtilityDecisionMaker::StateIndex(const std::string& name) const {
  for (size_t k = 0; k < options_.state_variables.size(); ++k)
    if (options_.state_variables[k] == name) return k;
  throw Error(ErrorCode::kInvalidArgument, "brain: no state variable named '" + name + "'");
}

std::vector<ProcessUtility> UtilityDecisionMaker::Snapshot() const {
  std::vector<ProcessUtility> out;
  for (size_t i = 0; i < size(); ++i) {
    out.push_back({options_.processes[i].name, options_.processes[i].kind, utility_[i], gamma_[i], active_[i]});
  }
  return out;
}

UtilityBrainOptions DefaultBrainOptions() {
  UtilityBrainOptions o;
  o.state_variables = {"contact", "sensors_stale", "localization_lost", "moving_obstacle_danger", "map_building"};
  UtilityProcessOptions navigation{"navigation", ProcessKind::kMotor, 0.1, 1.0, 0.25, {}};
  UtilityProcessOptions stop{
      "emergency_stop", ProcessKind::kMotor, 0.05, 5.0, 0.0, {{"contact", 1.0}, {"sensors_stale", 1.0}}};
  UtilityProcessOptions wake_up{"wake_up", ProcessKind::kMotor, 0.1, 3.0, -0.2, {{"localization_lost", 1.0}}};
  // Seed 000 section 6: a_51 = 1, b_5 = -0.45, tau 0.1 s, Gamma_5 = 3 on activation decaying in 1 s.
  UtilityProcessOptions avoidance{
      "moving_obstacle_avoidance", ProcessKind::kMotor, 0.1, 1.0, -0.45, {{"moving_obstacle_danger", 1.0}}, 1.0, 3.0};
  UtilityProcessOptions localization{"localization", ProcessKind::kCognitive, 0.1, 1.0, 0.5, {}};
  UtilityProcessOptions detection{"moving_obstacle_detection", ProcessKind::kCognitive, 0.1, 1.0, 0.5,
                                  {{"map_building", -1.0}}};
  // Seed 000 section 4.6: B6 keeps the map for the others; off while the map is being built.
  UtilityProcessOptions memory{"long_term_memory", ProcessKind::kCognitive, 0.1, 1.0, 0.5, {{"map_building", -1.0}}};
  o.processes = {navigation, stop, wake_up, avoidance, localization, detection, memory};
  return o;
}

UtilityBrainOptions ParseBrain(const std::string& text, const std::string& source) {
  const YamlFields f(source);
  const YAML::Node doc = ParseYamlMapping(text, source);
  f.CheckKeys(doc, "", {"state_variables", "processes", "initial_utility"});
  UtilityBrainOptions o;
  if (doc["initial_utility"]) o.initial_utility = f.Number(doc["initial_utility"], "initial_utility");
  f.ExpectSequence(doc["state_variables"], "state_variables", "names");
  for (size_t k = 0; k < doc["state_variables"].size(); ++k) {
    o.state_variables.push_back(f.String(doc["state_variables"][k], "state_variables[" + std::to_string(k) + "]"));
  }
  const YAML::Node ps = doc["processes"];
  f.ExpectSequence(ps, "processes", "processes");
  for (size_t i = 0; i < ps.size(); ++i) {
    const std::string at = "processes[" + std::to_string(i) + "].";
    const YAML::Node n = ps[i];
    f.ExpectMap(n, "processes[" + std::to_string(i) + "]");
    f.CheckKeys(n, at, {"name", "kind", "tau", "c", "b", "a", "gamma_tau", "gamma_on_activation"});
    UtilityProcessOptions p;
    if (!n["name"]) f.Fail(at + "name", "is required", n);
    p.name = f.String(n["name"], at + "name");
    if (!n["kind"]) f.Fail(at + "kind", "is required (motor or cognitive)", n);
    p.kind =
        f.Choice(n["kind"], at + "kind", {"motor", "cognitive"}) == 0 ? ProcessKind::kMotor : ProcessKind::kCognitive;
    f.Read(n, "tau", at, p.tau, &YamlFields::Positive);
    f.Read(n, "c", at, p.c, &YamlFields::Positive);
    f.Read(n, "b", at, p.b, &YamlFields::Number);
    f.Read(n, "gamma_tau", at, p.gamma_tau, &YamlFields::Positive);
    f.Read(n, "gamma_on_activation", at, p.gamma_on_activation, &YamlFields::Number);
    if (n["a"]) {
      f.ExpectMap(n["a"], at + "a");
      for (const auto& kv : n["a"]) {
        const std::string var = kv.first.as<std::string>();
        const bool known =
            std::find(o.state_variables.begin(), o.state_variables.end(), var) != o.state_variables.end();
        if (!known) f.Fail(at + "a." + var, "is not one of state_variables", kv.first);
        p.a.emplace_back(var, f.Number(kv.second, at + "a." + var));
      }
    }
    o.processes.push_back(std::move(p));
  }
  try {
    UtilityDecisionMaker check(o);  // the remaining rules (a motor behaviour, unique names)
  } catch (const Error& e) {
    throw Error(e.code(), source + ": " + e.what());
  }
  return o;
}

UtilityBrainOptions LoadBrainFile(const std::string& path) {
  return ParseBrain(ReadTextFile(path, "brain file"), path);
}

}  // namespace navd::navigation
