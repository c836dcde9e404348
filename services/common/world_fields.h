#pragma once
// The robot and laser sections shared by world files and simulator scenarios: each field present
// in the YAML mapping overrides the description's default, with errors that name file, line and
// field (prefix + key, e.g. "robots[0].radius").
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "services/common/world.h"
#include "services/common/yaml_fields.h"

namespace navd {

// `extra_keys`: further keys the caller reads itself (a scenario's robot has a name and sensors).
void ReadRobotDescription(const YamlFields& fields, const YAML::Node& node, const std::string& prefix,
                          RobotDescription& out, const std::vector<std::string>& extra_keys = {});
void ReadLaserDescription(const YamlFields& fields, const YAML::Node& node, const std::string& prefix,
                          LaserDescription& out);
void ReadDepthCameraDescription(const YamlFields& fields, const YAML::Node& node, const std::string& prefix,
                                DepthCameraDescription& out);
// [x_min, y_min, x_max, y_max] with min <= max.
Box ReadBox(const YamlFields& fields, const YAML::Node& node, const std::string& field);

}  // namespace navd
