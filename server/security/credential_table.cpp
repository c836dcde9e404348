#include "server/security/credential_table.h"

#include <sys/stat.h>

#include <cstdio>
#include <sstream>

#include "services/common/error.h"
#include "services/common/text_file.h"

namespace navd::server::security {
namespace {

constexpr size_t kMinTokenLength = 16;
constexpr std::string_view kCommonNamePrefix = "cn:";

bool EqualInConstantTime(std::string_view a, std::string_view b) {
  // The length of a guess is the caller's own; only its content is secret.
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

[[noreturn]] void Fail(const std::string& source, int line, const std::string& what) {
  throw Error(ErrorCode::kInvalidArgument, source + " line " + std::to_string(line) + ": " + what);
}

}  // namespace

CredentialTable CredentialTable::Load(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    throw Error(ErrorCode::kInvalidArgument, "auth tokens file " + path + " cannot be read");
  }
  if ((st.st_mode & (S_IRWXG | S_IRWXO)) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    throw Error(ErrorCode::kInvalidArgument,
                "auth tokens file " + path + " is open to group or others (mode " + mode + "); chmod 600 " + path);
  }
  return Parse(ReadTextFile(path, "auth tokens file"), path);
}

CredentialTable CredentialTable::Parse(const std::string& text, const std::string& source) {
  CredentialTable table;
  std::istringstream lines(text);
  std::string line;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    std::string key, role_name, extra;
    if (!(fields >> key)) continue;
    if (!(fields >> role_name) || (fields >> extra)) Fail(source, number, "expected TOKEN ROLE or cn:NAME ROLE");
    const std::optional<Role> role = ParseRole(role_name);
    if (!role) Fail(source, number, "unknown role '" + role_name + "' (viewer, operator or admin)");
    if (key.rfind(kCommonNamePrefix, 0) == 0) {
      std::string name = key.substr(kCommonNamePrefix.size());
      if (name.empty()) Fail(source, number, "cn: needs a certificate common name");
      for (const Entry& e : table.common_names_) {
        if (e.key == name) Fail(source, number, "common name '" + name + "' given twice");
      }
      table.common_names_.push_back({std::move(name), *role});
      continue;
    }
    if (key.size() < kMinTokenLength) {
      Fail(source, number, "token shorter than " + std::to_string(kMinTokenLength) + " characters");
    }
    if (table.RoleOfToken(key)) Fail(source, number, "token given twice");
    table.tokens_.push_back({std::move(key), *role});
  }
  return table;
}

std::optional<Role> CredentialTable::RoleOfToken(std::string_view token) const {
  std::optional<Role> found;
  for (const Entry& e : tokens_) {
    if (EqualInConstantTime(e.key, token)) found = e.role;
  }
  return found;
}

std::optional<Role> CredentialTable::RoleOfCommonName(std::string_view common_name) const {
  for (const Entry& e : common_names_) {
    if (e.key == common_name) return e.role;
  }
  return std::nullopt;
}

}  // namespace navd::server::security
