#include "server/security/role_authorizer.h"

#include <grpc/grpc_security_constants.h>
#include <grpcpp/security/auth_context.h>
#include <spdlog/spdlog.h>

#include <string>

namespace navd::server::security {
namespace {

constexpr std::string_view kBearer = "Bearer ";

std::string_view Lookup(const grpc::AuthMetadataProcessor::InputMetadata& metadata, std::string_view key) {
  const auto it = metadata.find(grpc::string_ref(key.data(), key.size()));
  if (it == metadata.end()) return {};
  return {it->second.data(), it->second.size()};
}

// "/navd.v1.NavigationService/NavigateTo" -> "NavigationService.NavigateTo"
std::string MethodName(std::string_view path) {
  const size_t slash = path.rfind('/');
  std::string_view service = path.substr(0, slash == std::string_view::npos ? 0 : slash);
  if (const size_t dot = service.rfind('.'); dot != std::string_view::npos) service.remove_prefix(dot + 1);
  if (!service.empty() && service.front() == '/') service.remove_prefix(1);
  const std::string_view method = slash == std::string_view::npos ? path : path.substr(slash + 1);
  return std::string(service) + "." + std::string(method);
}

}  // namespace

RoleAuthorizer::RoleAuthorizer(CredentialTable table)
    : table_(std::make_shared<const CredentialTable>(std::move(table))) {}

void RoleAuthorizer::Replace(CredentialTable table) {
  auto next = std::make_shared<const CredentialTable>(std::move(table));
  std::lock_guard lock(mutex_);
  table_ = std::move(next);
}

std::shared_ptr<const CredentialTable> RoleAuthorizer::Table() const {
  std::lock_guard lock(mutex_);
  return table_;
}

grpc::Status RoleAuthorizer::Process(const InputMetadata& metadata, grpc::AuthContext* context,
                                     OutputMetadata* consumed, OutputMetadata*) {
  const std::string_view path = Lookup(metadata, ":path");
  const std::optional<Role> required = RequiredRole(path);
  if (!required) return grpc::Status::OK;
  // Messages are built only for refusals: an admitted call costs two lookups and a table scan.
  const auto refuse = [&](grpc::StatusCode code, const std::string& why) {
    return grpc::Status(code, MethodName(path) + why);
  };
  const std::shared_ptr<const CredentialTable> table = Table();

  std::optional<Role> role;
  std::string_view common_name;  // of the client certificate that gave the role; empty: a token
  const std::string_view authorization = Lookup(metadata, "authorization");
  if (!authorization.empty()) {
    consumed->emplace("authorization", std::string(authorization));
    if (authorization.substr(0, kBearer.size()) != kBearer) {
      return refuse(grpc::StatusCode::UNAUTHENTICATED, ": the authorization metadata must be 'Bearer <token>'");
    }
    role = table->RoleOfToken(authorization.substr(kBearer.size()));
    if (!role) return refuse(grpc::StatusCode::UNAUTHENTICATED, ": navd does not know this bearer token");
  } else if (context != nullptr && context->IsPeerAuthenticated()) {
    for (const grpc::string_ref& cn : context->FindPropertyValues(GRPC_X509_CN_PROPERTY_NAME)) {
      role = table->RoleOfCommonName(std::string_view(cn.data(), cn.size()));
      if (role) {
        common_name = std::string_view(cn.data(), cn.size());
        break;
      }
    }
    if (!role) {
      return refuse(grpc::StatusCode::UNAUTHENTICATED,
                    ": the client certificate's common name has no role in the auth tokens file");
    }
  } else {
    return refuse(grpc::StatusCode::UNAUTHENTICATED,
                  " needs credentials: a bearer token (authorization: Bearer <token>) or a client certificate");
  }
  if (*role < *required) {
    spdlog::info("navd: refused {} to role {} ({})", MethodName(path), RoleName(*role),
                 common_name.empty() ? std::string("token") : "certificate '" + std::string(common_name) + "'");
    return refuse(grpc::StatusCode::PERMISSION_DENIED,
                  std::string(" needs the ") + RoleName(*required) + " role; the caller's role is " + RoleName(*role));
  }
  return grpc::Status::OK;
}

}  // namespace navd::server::security
