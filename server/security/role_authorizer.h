#pragma once
// Checks every gRPC call against the credential table before navd's handlers see it: the caller's
// bearer token (metadata "authorization: Bearer <token>") or, with mutual TLS, its certificate's
// common name gives a role, and the method's required role (role.h) must not be above it.
//   no credential, or one navd does not know -> UNAUTHENTICATED
//   a known caller with too little role      -> PERMISSION_DENIED
// Both messages name the method. The token is consumed here, so handlers and logs never see it.
// The table can be swapped while calls run (SIGHUP reloads the file).
#include <grpcpp/security/auth_metadata_processor.h>

#include <memory>
#include <mutex>
#include <optional>
#include <string_view>

#include "server/security/credential_table.h"

namespace navd::server::security {

class RoleAuthorizer : public grpc::AuthMetadataProcessor {
 public:
  explicit RoleAuthorizer(CredentialTable table);

  // A lookup in a small table: cheap enough to run on gRPC's own thread.
  bool IsBlocking() const override { return false; }
  grpc::Status Process(const InputMetadata& metadata, grpc::AuthContext* context, OutputMetadata* consumed,
                       OutputMetadata* response) override;

  void Replace(CredentialTable table);
  // The role of a bearer token in the current table; nullopt for one it does not know. For the
  // other listeners that take navd's tokens (the live view).
  std::optional<Role> RoleOfToken(std::string_view token) const { return Table()->RoleOfToken(token); }

 private:
  std::shared_ptr<const CredentialTable> Table() const;

  mutable std::mutex mutex_;
  std::shared_ptr<const CredentialTable> table_;
};

}  // namespace navd::server::security
