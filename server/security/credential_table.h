#pragma once
// The credentials navd accepts and the role each one carries, read from an --auth-tokens file:
//
//   # comment
//   <token> <role>          a bearer token (at least 16 characters, no spaces)
//   cn:<name> <role>        a client certificate whose subject common name is <name> (mutual TLS)
//
// Roles are viewer, operator and admin (role.h). The file holds secrets, so it is refused when
// its mode lets group or others read or write it, and no token ever appears in a message.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "server/security/role.h"

namespace navd::server::security {

class CredentialTable {
 public:
  // Throws navd::Error (kInvalidArgument) naming the file and line, never the token.
  static CredentialTable Load(const std::string& path);
  static CredentialTable Parse(const std::string& text, const std::string& source);

  // Compares against every token in constant time per token, so the time taken does not tell how
  // much of a guess was right.
  std::optional<Role> RoleOfToken(std::string_view token) const;
  std::optional<Role> RoleOfCommonName(std::string_view common_name) const;
  size_t token_count() const { return tokens_.size(); }
  size_t common_name_count() const { return common_names_.size(); }

 private:
  struct Entry {
    std::string key;
    Role role;
  };
  std::vector<Entry> tokens_;
  std::vector<Entry> common_names_;
};

}  // namespace navd::server::security
