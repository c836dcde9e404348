#pragma once
// Parses YAML text into a mapping node, turning yaml-cpp's exceptions into navd::Error that
// names the file.
#include <yaml-cpp/yaml.h>

#include <string>

namespace navd {

// Throws navd::Error(kInvalidArgument) "<source>: malformed YAML: ..." or "<source>: expected a
// YAML mapping".
YAML::Node ParseYamlMapping(const std::string& text, const std::string& source);

}  // namespace navd
