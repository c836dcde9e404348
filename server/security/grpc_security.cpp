#include "server/security/grpc_security.h"

#include <grpcpp/security/server_credentials.h>
#include <spdlog/spdlog.h>

#include "server/security/credential_table.h"
#include "server/security/role_authorizer.h"
#include "services/common/error.h"
#include "services/common/text_file.h"

namespace navd::server::security {
namespace {

[[noreturn]] void Refuse(const std::string& message) { throw Error(ErrorCode::kInvalidArgument, message); }

std::string ReadPem(const std::string& path, const std::string& option, const char* marker) {
  std::string text;
  try {
    text = ReadTextFile(path, option);
  } catch (const Error&) {
    Refuse(option + " " + path + " cannot be read");
  }
  if (text.find(marker) == std::string::npos) Refuse(option + " " + path + " holds no PEM '" + marker + "' block");
  return text;
}

std::string Plural(size_t n, const char* what) { return std::to_string(n) + " " + what + (n == 1 ? "" : "s"); }

std::string DescribeTable(const CredentialTable& t) {
  return Plural(t.token_count(), "token") + " and " + Plural(t.common_name_count(), "certificate name");
}

}  // namespace

bool IsLoopbackAddress(const std::string& listen) {
  if (listen.rfind("unix:", 0) == 0 || listen.rfind("unix-abstract:", 0) == 0) return true;
  const size_t colon = listen.rfind(':');
  std::string host = listen.substr(0, colon == std::string::npos ? listen.size() : colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

GrpcSecurity::GrpcSecurity(const GrpcSecurityOptions& o, const std::string& listen) : options_(o) {
  const bool tls = !o.tls_cert.empty() || !o.tls_key.empty();
  if (tls && (o.tls_cert.empty() || o.tls_key.empty())) Refuse("--tls-cert and --tls-key go together");
  if (!tls && !o.tls_client_ca.empty()) Refuse("--tls-client-ca needs --tls-cert and --tls-key");
  if (tls && o.insecure) Refuse("--insecure contradicts --tls-cert: choose one");
  if (!tls && !o.auth_tokens.empty()) {
    Refuse("--auth-tokens needs --tls-cert and --tls-key: bearer tokens must not cross the network in plain text");
  }
  if (!tls) {
    if (!IsLoopbackAddress(listen) && !o.insecure) {
      Refuse("refusing to listen on " + listen +
             " in plain text: give --tls-cert and --tls-key, or --insecure to let anyone who reaches the port "
             "drive the robot");
    }
    plain_text_beyond_loopback_ = !IsLoopbackAddress(listen);
    credentials_ = grpc::InsecureServerCredentials();
    description_ = "plain text";
    return;
  }

  grpc::SslServerCredentialsOptions ssl(o.tls_client_ca.empty()
                                            ? GRPC_SSL_DONT_REQUEST_CLIENT_CERTIFICATE
                                            : GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY);
  ssl.pem_key_cert_pairs.push_back(
      {ReadPem(o.tls_key, "--tls-key", "PRIVATE KEY"), ReadPem(o.tls_cert, "--tls-cert", "BEGIN CERTIFICATE")});
  if (!o.tls_client_ca.empty()) ssl.pem_root_certs = ReadPem(o.tls_client_ca, "--tls-client-ca", "BEGIN CERTIFICATE");
  credentials_ = grpc::SslServerCredentials(ssl);
  description_ = o.tls_client_ca.empty() ? "TLS" : "mutual TLS (client certificates required)";
  if (!o.auth_tokens.empty()) {
    CredentialTable table = CredentialTable::Load(o.auth_tokens);
    description_ += ", roles for " + DescribeTable(table);
    authorizer_ = std::make_shared<RoleAuthorizer>(std::move(table));
    credentials_->SetAuthMetadataProcessor(authorizer_);
  } else {
    description_ += ", no roles (every client may call every method)";
  }
}

GrpcSecurity::~GrpcSecurity() = default;

std::string GrpcSecurity::Describe() const { return description_; }

void GrpcSecurity::ReloadCredentialTable() {
  if (!authorizer_) {
    spdlog::info("navd: SIGHUP: no --auth-tokens file to reload");
    return;
  }
  try {
    CredentialTable table = CredentialTable::Load(options_.auth_tokens);
    const std::string what = DescribeTable(table);
    authorizer_->Replace(std::move(table));
    spdlog::info("navd: reloaded {}: {}", options_.auth_tokens, what);
  } catch (const Error& e) {
    spdlog::error("navd: kept the previous credentials: {}", e.what());
  }
}

std::optional<Role> GrpcSecurity::RoleOfToken(std::string_view token) const {
  if (!authorizer_) return std::nullopt;
  return authorizer_->RoleOfToken(token);
}

}  // namespace navd::server::security
