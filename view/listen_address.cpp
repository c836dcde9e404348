#include <stdexcept>

#include "services/common/error.h"
#include "view/foxglove_server.h"

namespace navd::view {

void ParseListenAddress(const std::string& option, const std::string& text, FoxgloveServerOptions& options) {
  const size_t colon = text.rfind(':');
  int port = -1;
  if (colon != std::string::npos && colon > 0 && colon + 1 < text.size() && text.size() - colon <= 6) {
    try {
      size_t used = 0;
      port = std::stoi(text.substr(colon + 1), &used);
      if (used != text.size() - colon - 1) port = -1;
    } catch (const std::exception&) {
      port = -1;
    }
  }
  if (port < 0 || port > 65535) throw Error(ErrorCode::kInvalidArgument, option + ": '" + text + "' is not HOST:PORT");
  options.host = text.substr(0, colon);
  options.port = port;
}

}  // namespace navd::view
