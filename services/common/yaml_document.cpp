#include "services/common/yaml_document.h"

#include "services/common/error.h"

namespace navd {

YAML::Node ParseYamlMapping(const std::string& text, const std::string& source) {
  YAML::Node doc;
  try {
    doc = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw Error(ErrorCode::kInvalidArgument, source + ": malformed YAML: " + e.what());
  }
  if (!doc.IsMap()) throw Error(ErrorCode::kInvalidArgument, source + ": expected a YAML mapping");
  return doc;
}

}  // namespace navd
