#include "services/common/yaml_fields.h"

#include <cmath>

#include "services/common/error.h"

namespace navd {

void YamlFields::Fail(const std::string& field, const std::string& why, const YAML::Node& at) const {
  std::string where = source_;
  if (at.IsDefined() && at.Mark().line >= 0) where += ":" + std::to_string(at.Mark().line + 1);
  throw Error(ErrorCode::kInvalidArgument, where + ": field '" + field + "' " + why);
}

void YamlFields::CheckKeys(const YAML::Node& n, const std::string& where,
                           std::initializer_list<const char*> allowed) const {
  for (const auto& kv : n) {
    if (!kv.first.IsScalar())
      Fail(where.empty() ? "(top level)" : where, "has a key that is not a plain name", kv.first);
    const std::string key = kv.first.as<std::string>();
    bool known = false;
    std::string list;
    for (const char* a : allowed) {
      known |= key == a;
      list += (list.empty() ? "" : ", ") + std::string(a);
    }
    if (!known) Fail(where.empty() ? key : where + "." + key, "is not a known field (expected " + list + ")", kv.first);
  }
}

void YamlFields::ExpectMap(const YAML::Node& n, const std::string& field) const {
  if (n && !n.IsMap()) Fail(field, "must be a mapping", n);
}

void YamlFields::ExpectSequence(const YAML::Node& n, const std::string& field, const std::string& of) const {
  // A missing field is an invalid node, whose IsSequence() throws instead of answering.
  if (!n || !n.IsSequence()) Fail(field, "must be a list of " + of, n);
}

double YamlFields::Number(const YAML::Node& n, const std::string& field) const {
  double v = 0.0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    Fail(field, "must be a number", n);
  }
  if (!std::isfinite(v)) Fail(field, "must be finite", n);
  return v;
}

double YamlFields::Positive(const YAML::Node& n, const std::string& field) const {
  const double v = Number(n, field);
  if (v <= 0) Fail(field, "must be positive", n);
  return v;
}

double YamlFields::NonNegative(const YAML::Node& n, const std::string& field) const {
  const double v = Number(n, field);
  if (v < 0) Fail(field, "must not be negative", n);
  return v;
}

double YamlFields::Probability(const YAML::Node& n, const std::string& field) const {
  const double v = Number(n, field);
  if (v < 0 || v > 1) Fail(field, "must be between 0 and 1", n);
  return v;
}

int YamlFields::Integer(const YAML::Node& n, const std::string& field, int min, int max) const {
  const double v = Number(n, field);
  if (v != std::floor(v) || v < min || v > max) {
    Fail(field, "must be a whole number from " + std::to_string(min) + " to " + std::to_string(max), n);
  }
  return static_cast<int>(v);
}

bool YamlFields::Bool(const YAML::Node& n, const std::string& field) const {
  try {
    return n.as<bool>();
  } catch (const YAML::Exception&) {
    Fail(field, "must be true or false", n);
  }
}

std::string YamlFields::String(const YAML::Node& n, const std::string& field) const {
  if (!n.IsScalar()) Fail(field, "must be a string", n);
  return n.as<std::string>();
}

size_t YamlFields::Choice(const YAML::Node& n, const std::string& field,
                          std::initializer_list<const char*> options) const {
  const std::string value = String(n, field);
  std::string list;
  size_t i = 0;
  for (const char* o : options) {
    if (value == o) return i;
    list += (i == 0 ? "" : i + 1 == options.size() ? " or " : ", ") + std::string(o);
    ++i;
  }
  Fail(field, "must be " + list + " (got '" + value + "')", n);
}

std::vector<double> YamlFields::Numbers(const YAML::Node& n, const std::string& field, size_t min, size_t max) const {
  if (!n.IsSequence() || n.size() < min || n.size() > max) {
    Fail(field, "must be a list of " + std::to_string(min) + (min == max ? "" : "-" + std::to_string(max)) + " numbers",
         n);
  }
  std::vector<double> out;
  for (size_t i = 0; i < n.size(); ++i) out.push_back(Number(n[i], field + "[" + std::to_string(i) + "]"));
  return out;
}

Point2 YamlFields::PointOf(const YAML::Node& n, const std::string& field) const {
  const auto v = Numbers(n, field, 2, 2);
  return {v[0], v[1]};
}

Pose2 YamlFields::PoseOf(const YAML::Node& n, const std::string& field) const {
  const auto v = Numbers(n, field, 2, 3);
  return {v[0], v[1], v.size() > 2 ? NormalizeAngle(v[2]) : 0.0};
}

std::vector<Point2> YamlFields::Points(const YAML::Node& n, const std::string& field, size_t min) const {
  if (!n.IsSequence() || n.size() < min) {
    Fail(field, "must be a list of at least " + std::to_string(min) + " [x, y] points", n);
  }
  std::vector<Point2> out;
  for (size_t i = 0; i < n.size(); ++i) out.push_back(PointOf(n[i], field + "[" + std::to_string(i) + "]"));
  return out;
}

}  // namespace navd
