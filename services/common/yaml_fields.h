#pragma once
// Typed access to the fields of a YAML configuration file (worlds, scenarios) with errors that name
// the file, the line and the field: "<file>:<line>: field 'robots[1].start' must be a number".
// Unknown keys are errors too, since a misspelt key would otherwise be a silent default.
#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <string>
#include <vector>

#include "services/common/pose2.h"

namespace navd {

class YamlFields {
 public:
  explicit YamlFields(std::string source) : source_(std::move(source)) {}
  const std::string& source() const { return source_; }

  // Throws navd::Error(kInvalidArgument). `at` (when valid) supplies the line number.
  [[noreturn]] void Fail(const std::string& field, const std::string& why, const YAML::Node& at = YAML::Node()) const;

  void CheckKeys(const YAML::Node& n, const std::string& where, std::initializer_list<const char*> allowed) const;
  // A mapping or a missing node (then nothing to read); anything else fails.
  void ExpectMap(const YAML::Node& n, const std::string& field) const;
  void ExpectSequence(const YAML::Node& n, const std::string& field, const std::string& of) const;

  double Number(const YAML::Node& n, const std::string& field) const;
  double Positive(const YAML::Node& n, const std::string& field) const;
  double NonNegative(const YAML::Node& n, const std::string& field) const;
  double Probability(const YAML::Node& n, const std::string& field) const;
  int Integer(const YAML::Node& n, const std::string& field, int min, int max) const;
  bool Bool(const YAML::Node& n, const std::string& field) const;
  std::string String(const YAML::Node& n, const std::string& field) const;
  // One of `options` (a keyword); returns its index. Fails with "must be a, b or c (got 'x')".
  size_t Choice(const YAML::Node& n, const std::string& field, std::initializer_list<const char*> options) const;
  std::vector<double> Numbers(const YAML::Node& n, const std::string& field, size_t min, size_t max) const;
  Point2 PointOf(const YAML::Node& n, const std::string& field) const;
  // [x, y] or [x, y, theta]; theta normalised to (-pi, pi].
  Pose2 PoseOf(const YAML::Node& n, const std::string& field) const;
  // A list of [x, y] points with at least `min` entries.
  std::vector<Point2> Points(const YAML::Node& n, const std::string& field, size_t min) const;

  // Optional fields: assign only when present.
  void Read(const YAML::Node& parent, const char* key, const std::string& prefix, double& out,
            double (YamlFields::*check)(const YAML::Node&, const std::string&) const) const {
    if (parent[key]) out = (this->*check)(parent[key], prefix + key);
  }

 private:
  std::string source_;
};

}  // namespace navd
