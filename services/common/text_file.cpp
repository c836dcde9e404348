#include "services/common/text_file.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "services/common/error.h"

namespace navd {

std::string ReadTextFile(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (path.empty()) throw Error(ErrorCode::kInvalidArgument, what + ": path is empty");
  if (!std::filesystem::exists(path, ec)) throw Error(ErrorCode::kNotFound, what + " '" + path + "' does not exist");
  if (std::filesystem::is_directory(path, ec)) {
    throw Error(ErrorCode::kInvalidArgument, what + " '" + path + "' is a directory");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorCode::kInvalidArgument, what + " '" + path + "' cannot be read");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw Error(ErrorCode::kInvalidArgument, what + " '" + path + "' cannot be read");
  std::string s = ss.str();
  if (s.empty()) throw Error(ErrorCode::kInvalidArgument, what + " '" + path + "' is empty");
  return s;
}

void WriteFileAtomically(const std::string& path, const std::string& contents) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(ErrorCode::kInvalidArgument, "cannot write '" + tmp + "'");
    out << contents;
    out.flush();
    if (!out) {
      std::remove(tmp.c_str());
      throw Error(ErrorCode::kInternal, "short write to '" + tmp + "'");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw Error(ErrorCode::kInternal, "cannot rename '" + tmp + "' to '" + path + "'");
  }
}

}  // namespace navd
