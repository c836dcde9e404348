#pragma once
// How navd's gRPC listener is secured, from navd's --tls-* / --auth-tokens / --insecure options:
//   TLS with --tls-cert and --tls-key; mutual TLS when --tls-client-ca is given (clients without a
//   certificate that CA signed cannot connect); roles from --auth-tokens (role_authorizer.h).
// Listening beyond loopback in plain text is refused unless --insecure says so: anyone who reaches
// the port could drive the robot.
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "server/security/role.h"

namespace grpc {
class ServerCredentials;
}

namespace navd::server::security {

class RoleAuthorizer;

struct GrpcSecurityOptions {
  std::string tls_cert;       // PEM certificate chain of the server
  std::string tls_key;        // PEM private key of that certificate
  std::string tls_client_ca;  // PEM CA bundle; set: clients must present a certificate it signed
  std::string auth_tokens;    // credential table file (credential_table.h); empty: no roles
  bool insecure = false;      // allow plain text beyond loopback
};

// True for 127.0.0.0/8, ::1, localhost and unix: sockets.
bool IsLoopbackAddress(const std::string& listen);

class GrpcSecurity {
 public:
  // Throws navd::Error (kInvalidArgument) for options that contradict each other or the listen
  // address, and for files that cannot be read; each message names the option.
  GrpcSecurity(const GrpcSecurityOptions& options, const std::string& listen);
  ~GrpcSecurity();

  std::shared_ptr<grpc::ServerCredentials> Credentials() const { return credentials_; }
  // One line for the start-up log: "TLS, client certificates required, 3 tokens and 1 certificate name".
  std::string Describe() const;
  // Re-reads --auth-tokens. On error the old table stays and the error is logged.
  void ReloadCredentialTable();
  bool warns_plain_text_beyond_loopback() const { return plain_text_beyond_loopback_; }
  // Whether --auth-tokens gives roles, and the role of a bearer token in the current table
  // (nullopt: unknown, or no table). The live view checks its clients' tokens with these.
  bool has_roles() const { return authorizer_ != nullptr; }
  std::optional<Role> RoleOfToken(std::string_view token) const;

 private:
  GrpcSecurityOptions options_;
  std::shared_ptr<RoleAuthorizer> authorizer_;
  std::shared_ptr<grpc::ServerCredentials> credentials_;
  std::string description_;
  bool plain_text_beyond_loopback_ = false;
};

}  // namespace navd::server::security
