#pragma once
#include <string>

namespace navd {

// Reads a whole file. Throws navd::Error: kNotFound when it does not exist, kInvalidArgument when it
// cannot be read or is empty. `what` names the file's role in the message ("map file").
std::string ReadTextFile(const std::string& path, const std::string& what);

// Writes a file atomically: a temporary file beside it, then rename, so readers never see half.
void WriteFileAtomically(const std::string& path, const std::string& contents);

}  // namespace navd
