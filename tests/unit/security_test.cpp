// The rules of navd's gRPC security that need no network: the credential table file, the role of
// each method, and which listener settings navd refuses.
#include <gtest/gtest.h>
#include <google/protobuf/descriptor.h>
#include <sys/stat.h>

#include <fstream>

#include "navd/v1/localization.grpc.pb.h"
#include "navd/v1/mapping.grpc.pb.h"
#include "navd/v1/navigation.grpc.pb.h"
#include "navd/v1/planning.grpc.pb.h"
#include "server/security/credential_table.h"
#include "server/security/grpc_security.h"
#include "server/security/role.h"
#include "services/common/error.h"
#include "tests/support/process.h"

namespace navd::server::security {
namespace {

const std::string kViewerToken = "0123456789abcdef-viewer";
const std::string kAdminToken = "fedcba9876543210-admin!";

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(CredentialTable, GivesEachTokenAndCertificateNameItsRole) {
  const CredentialTable t = CredentialTable::Parse("# navd tokens\n\n" + kViewerToken + " viewer\n" + kAdminToken +
                                                       "   admin  # the robot's owner\ncn:navctl operator\n",
                                                   "tokens");
  EXPECT_EQ(t.token_count(), 2u);
  EXPECT_EQ(t.common_name_count(), 1u);
  EXPECT_EQ(t.RoleOfToken(kViewerToken), Role::kViewer);
  EXPECT_EQ(t.RoleOfToken(kAdminToken), Role::kAdmin);
  EXPECT_EQ(t.RoleOfCommonName("navctl"), Role::kOperator);
  EXPECT_FALSE(t.RoleOfToken(kViewerToken.substr(0, kViewerToken.size() - 1)));
  EXPECT_FALSE(t.RoleOfToken(kViewerToken + "x"));
  EXPECT_FALSE(t.RoleOfToken(""));
  EXPECT_FALSE(t.RoleOfCommonName("navd"));
}

TEST(CredentialTable, BadLinesNameTheLineAndNeverTheToken) {
  const auto error = [](const std::string& text) { return ErrorOf([&] { CredentialTable::Parse(text, "tokens"); }); };
  std::string e = error(kViewerToken + " viewer\n" + kAdminToken + " root\n");
  EXPECT_NE(e.find("tokens line 2"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown role 'root'"), std::string::npos) << e;
  EXPECT_EQ(e.find(kAdminToken), std::string::npos) << e;
  e = error("short viewer\n");
  EXPECT_NE(e.find("line 1: token shorter than 16"), std::string::npos) << e;
  e = error(kAdminToken + "\n");
  EXPECT_NE(e.find("expected TOKEN ROLE"), std::string::npos) << e;
  EXPECT_EQ(e.find(kAdminToken), std::string::npos) << e;
  e = error(kAdminToken + " admin extra\n");
  EXPECT_NE(e.find("expected TOKEN ROLE"), std::string::npos) << e;
  e = error(kAdminToken + " admin\n" + kAdminToken + " viewer\n");
  EXPECT_NE(e.find("line 2: token given twice"), std::string::npos) << e;
  EXPECT_EQ(e.find(kAdminToken), std::string::npos) << e;
  e = error("cn: viewer\n");
  EXPECT_NE(e.find("needs a certificate common name"), std::string::npos) << e;
}

TEST(CredentialTable, RefusesAFileGroupOrOthersCanRead) {
  const std::string path = testing::MakeTempDir() + "/tokens";
  std::ofstream(path) << kAdminToken << " admin\n";
  ASSERT_EQ(::chmod(path.c_str(), 0644), 0);
  const std::string e = ErrorOf([&] { CredentialTable::Load(path); });
  EXPECT_NE(e.find("open to group or others (mode 0644); chmod 600 " + path), std::string::npos) << e;
  ASSERT_EQ(::chmod(path.c_str(), 0600), 0);
  EXPECT_EQ(CredentialTable::Load(path).RoleOfToken(kAdminToken), Role::kAdmin);
  EXPECT_NE(ErrorOf([&] { CredentialTable::Load(path + ".missing"); }).find("cannot be read"), std::string::npos);
}

TEST(MethodRoles, EveryNavdMethodHasItsRoleAndHealthIsOpen) {
  // Every RPC in the services' descriptors is in the table, and the table names no other: a
  // method added to a .proto without a role here fails this test (and is admin-only meanwhile).
  std::vector<std::string> described;
  // Each service found through a message of its own .proto, which links that file's descriptor.
  for (const google::protobuf::ServiceDescriptor* s :
       {v1::ComputePathRequest::descriptor()->file()->FindServiceByName("PlanningService"),
        v1::GetPoseRequest::descriptor()->file()->FindServiceByName("LocalizationService"),
        v1::GetMapRequest::descriptor()->file()->FindServiceByName("MappingService"),
        v1::NavigateToRequest::descriptor()->file()->FindServiceByName("NavigationService")}) {
    ASSERT_NE(s, nullptr);
    for (int i = 0; i < s->method_count(); ++i) described.push_back("/" + s->full_name() + "/" + s->method(i)->name());
  }
  std::vector<std::string> table = MethodsWithRoles();
  std::sort(described.begin(), described.end());
  std::sort(table.begin(), table.end());
  EXPECT_EQ(described, table);

  EXPECT_EQ(RequiredRole("/navd.v1.LocalizationService/GetPose"), Role::kViewer);
  EXPECT_EQ(RequiredRole("/navd.v1.MappingService/StreamMapUpdates"), Role::kViewer);
  EXPECT_EQ(RequiredRole("/navd.v1.NavigationService/NavigateTo"), Role::kOperator);
  EXPECT_EQ(RequiredRole("/navd.v1.PlanningService/ComputePath"), Role::kOperator);
  EXPECT_EQ(RequiredRole("/navd.v1.MappingService/StartExploration"), Role::kOperator);
  EXPECT_EQ(RequiredRole("/navd.v1.MappingService/LoadMap"), Role::kAdmin);
  EXPECT_EQ(RequiredRole("/navd.v1.LocalizationService/SetPose"), Role::kAdmin);
  EXPECT_EQ(RequiredRole("/navd.v1.LocalizationService/SelectMethod"), Role::kAdmin);
  EXPECT_EQ(RequiredRole("/navd.v1.MappingService/StartMapping"), Role::kAdmin);
  EXPECT_EQ(RequiredRole("/navd.v1.NavigationService/Unknown"), Role::kAdmin);
  EXPECT_EQ(RequiredRole(""), Role::kAdmin);
  EXPECT_FALSE(RequiredRole("/grpc.health.v1.Health/Check"));
  EXPECT_FALSE(RequiredRole("/grpc.health.v1.Health/Watch"));
}

TEST(GrpcSecurity, RefusesPlainTextBeyondLoopbackAndContradictoryOptions) {
  const auto error = [](const GrpcSecurityOptions& o, const std::string& listen) {
    return ErrorOf([&] { GrpcSecurity(o, listen); });
  };
  EXPECT_TRUE(IsLoopbackAddress("127.0.0.1:50051"));
  EXPECT_TRUE(IsLoopbackAddress("localhost:0"));
  EXPECT_TRUE(IsLoopbackAddress("[::1]:50051"));
  EXPECT_TRUE(IsLoopbackAddress("unix:/run/navd.sock"));
  EXPECT_FALSE(IsLoopbackAddress("0.0.0.0:50051"));
  EXPECT_FALSE(IsLoopbackAddress("[::]:50051"));
  EXPECT_FALSE(IsLoopbackAddress("10.0.0.7:50051"));
  EXPECT_FALSE(IsLoopbackAddress("navd.robots.svc:50051"));

  GrpcSecurityOptions o;
  std::string e = error(o, "0.0.0.0:50051");
  EXPECT_NE(e.find("refusing to listen on 0.0.0.0:50051 in plain text"), std::string::npos) << e;
  EXPECT_NE(e.find("--insecure"), std::string::npos) << e;
  EXPECT_EQ(error(o, "127.0.0.1:50051"), "");
  o.insecure = true;
  EXPECT_EQ(error(o, "0.0.0.0:50051"), "");
  EXPECT_TRUE(GrpcSecurity(o, "0.0.0.0:50051").warns_plain_text_beyond_loopback());
  EXPECT_FALSE(GrpcSecurity(o, "127.0.0.1:50051").warns_plain_text_beyond_loopback());

  o = {};
  o.auth_tokens = "tokens";
  EXPECT_NE(error(o, "127.0.0.1:0").find("--auth-tokens needs --tls-cert"), std::string::npos);
  o = {};
  o.tls_cert = "navd.pem";
  EXPECT_NE(error(o, "127.0.0.1:0").find("--tls-cert and --tls-key go together"), std::string::npos);
  o = {};
  o.tls_client_ca = "ca.pem";
  EXPECT_NE(error(o, "127.0.0.1:0").find("--tls-client-ca needs --tls-cert"), std::string::npos);
  o = {};
  o.tls_cert = "/nonexistent/navd.pem";
  o.tls_key = "/nonexistent/navd.key";
  e = error(o, "127.0.0.1:0");
  EXPECT_NE(e.find("/nonexistent/navd"), std::string::npos) << e;
  EXPECT_NE(e.find("cannot be read"), std::string::npos) << e;
  o.insecure = true;
  EXPECT_NE(error(o, "127.0.0.1:0").find("--insecure contradicts --tls-cert"), std::string::npos);
}

}  // namespace
}  // namespace navd::server::security
