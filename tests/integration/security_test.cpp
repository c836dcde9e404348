// navd's gRPC security against real processes over loopback: TLS, mutual TLS and roles, with the
// keystore scripts/make-keystore makes. Every refusal is checked for its status, for naming the
// method, and for having changed nothing (the robot stands still, the map is the same).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>

#include <chrono>
#include <fstream>
#include <functional>
#include <thread>

#include "services/common/text_file.h"
#include "tests/support/keystore.h"
#include "tests/support/navd_fixture.h"

namespace navd::testing {
namespace {

using grpc::StatusCode;

StackOptions SecuredStack(const Keystore& keys, bool client_ca, const std::string& client_role = "admin",
                          const std::string& client_cert = "") {
  StackOptions o;
  o.navd_args = {"--tls-cert", keys.tls("navd.pem"), "--tls-key", keys.tls("navd.key"), "--auth-tokens", keys.tokens()};
  if (client_ca) o.navd_args.insert(o.navd_args.end(), {"--tls-client-ca", keys.tls("ca.pem")});
  o.client = keys.Client(client_role, client_cert);
  return o;
}

// Runs `call`, which must fail with `code` and a message containing `words`.
::testing::AssertionResult FailsWith(const std::function<void()>& call, StatusCode code, const std::string& words) {
  try {
    call();
  } catch (const ClientError& e) {
    if (e.code() != code)
      return ::testing::AssertionFailure() << "status " << e.code() << " (" << e.what() << "), expected " << code;
    if (std::string(e.what()).find(words) == std::string::npos)
      return ::testing::AssertionFailure() << "message '" << e.what() << "' lacks '" << words << "'";
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "the call succeeded; expected status " << code;
}

// The robot did not move and navd holds no goal.
::testing::AssertionResult NothingMoved(NavdStack& stack, const Telemetry& telemetry) {
  const v1::GetStatusResponse s = stack.client().GetStatus();
  if (s.active()) return ::testing::AssertionFailure() << "navd holds a goal: " << s.ShortDebugString();
  return RobotStandsStill(telemetry);
}

bool WaitUntil(const std::function<bool()>& done, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return done();
}

TEST(GrpcSecurity, CallsWithoutEnoughRoleAreRefusedAndChangeNothing) {
  const Keystore keys;
  NavdStack stack(SecuredStack(keys, false));
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  const auto telemetry = stack.MakeTelemetry();
  const std::string office = SourceDir() + "/worlds/office.yaml";
  ASSERT_EQ(stack.client().GetMap(true).info().name(), "warehouse");

  const auto anonymous = stack.MakeClient(keys.Client(""));
  EXPECT_TRUE(FailsWith([&] { anonymous->NavigateTo(3.0, 4.0, std::nullopt, {}, 5.0); }, StatusCode::UNAUTHENTICATED,
                        "NavigationService.NavigateTo needs credentials"));
  EXPECT_TRUE(FailsWith([&] { anonymous->GetPose(); }, StatusCode::UNAUTHENTICATED, "GetPose"));
  EXPECT_EQ(anonymous->Health(), grpc::health::v1::HealthCheckResponse::SERVING);  // probes need no token

  ClientOptions forged = keys.Client("");
  forged.token = std::string(48, 'f');
  const auto wrong = stack.MakeClient(forged);
  EXPECT_TRUE(FailsWith([&] { wrong->NavigateTo(3.0, 4.0, std::nullopt, {}, 5.0); }, StatusCode::UNAUTHENTICATED,
                        "NavigateTo: navd does not know this bearer token"));
  EXPECT_TRUE(FailsWith([&] { wrong->LoadMap(office); }, StatusCode::UNAUTHENTICATED, "LoadMap"));

  const auto viewer = stack.MakeClient(keys.Client("viewer"));
  EXPECT_NO_THROW(viewer->GetPose());
  EXPECT_NO_THROW(viewer->ListPlanners());
  EXPECT_TRUE(FailsWith([&] { viewer->NavigateTo(3.0, 4.0, std::nullopt, {}, 5.0); }, StatusCode::PERMISSION_DENIED,
                        "NavigationService.NavigateTo needs the operator role; the caller's role is viewer"));
  EXPECT_TRUE(FailsWith([&] { viewer->ComputePath(1.0, 1.0, 3.0, 4.0); }, StatusCode::PERMISSION_DENIED,
                        "ComputePath needs the operator role"));
  EXPECT_TRUE(NothingMoved(stack, *telemetry));

  const auto operator_client = stack.MakeClient(keys.Client("operator"));
  EXPECT_NO_THROW(operator_client->ComputePath(1.0, 1.0, 3.0, 4.0));
  EXPECT_TRUE(FailsWith([&] { operator_client->LoadMap(office); }, StatusCode::PERMISSION_DENIED,
                        "MappingService.LoadMap needs the admin role; the caller's role is operator"));
  EXPECT_TRUE(FailsWith([&] { operator_client->SetPose(2.0, 2.0, 0.0); }, StatusCode::PERMISSION_DENIED, "SetPose"));
  EXPECT_TRUE(FailsWith([&] { operator_client->SelectMethod("ekf"); }, StatusCode::PERMISSION_DENIED, "SelectMethod"));
  EXPECT_EQ(stack.client().GetMap(true).info().name(), "warehouse");
  EXPECT_TRUE(NothingMoved(stack, *telemetry));

  // The admin may: so the refusals above were the roles' doing.
  EXPECT_EQ(stack.client().LoadMap(office).name(), "office");

  const std::string log = stack.navd().Log();
  for (const char* role : {"viewer", "operator", "admin"}) {
    EXPECT_EQ(log.find(keys.token(role)), std::string::npos) << "navd logged the " << role << " token";
  }
  EXPECT_EQ(log.find(forged.token), std::string::npos) << "navd logged a forged token";
  EXPECT_NE(log.find("refused NavigationService.NavigateTo to role viewer"), std::string::npos) << log;
}

TEST(GrpcSecurity, MutualTlsAdmitsOnlyCertificatesItsCaSignedWithARole) {
  const Keystore keys;
  const std::string foreign = keys.ExtraClientCertificate("foreign", "navctl", true, 30);
  const std::string expired = keys.ExtraClientCertificate("expired", "navctl", false, -1);
  const std::string stranger = keys.ExtraClientCertificate("stranger", "stranger", false, 30);
  // The stack's own client is the keystore's navctl certificate, an operator by its common name.
  NavdStack stack(SecuredStack(keys, true, "", keys.tls("navctl")));
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  const auto telemetry = stack.MakeTelemetry();

  EXPECT_NO_THROW(stack.client().ComputePath(1.0, 1.0, 3.0, 4.0));
  EXPECT_TRUE(FailsWith([&] { stack.client().LoadMap(SourceDir() + "/worlds/office.yaml"); },
                        StatusCode::PERMISSION_DENIED, "LoadMap needs the admin role; the caller's role is operator"));

  // Not even the admin token gets a connection without a certificate the CA signed and in date.
  for (const auto& [what, cert] : std::vector<std::pair<std::string, std::string>>{
           {"no certificate", ""}, {"another CA's certificate", foreign}, {"an expired certificate", expired}}) {
    const auto c = stack.MakeClient(keys.Client("admin", cert));
    EXPECT_TRUE(FailsWith([&] { c->NavigateTo(3.0, 4.0, std::nullopt, {}, 5.0); }, StatusCode::UNAVAILABLE,
                          "cannot reach navd"))
        << what;
  }
  const auto plain = stack.MakeClient(ClientOptions{"", 5.0});
  EXPECT_TRUE(FailsWith([&] { plain->NavigateTo(3.0, 4.0, std::nullopt, {}, 5.0); }, StatusCode::UNAVAILABLE,
                        "cannot reach navd"))
      << "a plain-text client";
  const auto unnamed = stack.MakeClient(keys.Client("", stranger));
  EXPECT_TRUE(FailsWith([&] { unnamed->NavigateTo(3.0, 4.0, std::nullopt, {}, 5.0); }, StatusCode::UNAUTHENTICATED,
                        "NavigateTo: the client certificate's common name has no role"));
  EXPECT_TRUE(NothingMoved(stack, *telemetry));
}

TEST(GrpcSecurity, PlainTextAgainstTlsIsRefused) {
  const Keystore keys;
  StackOptions o = SecuredStack(keys, false);
  o.start_sim = false;
  NavdStack stack(o);
  const auto plain = stack.MakeClient(ClientOptions{"", 5.0});
  EXPECT_TRUE(FailsWith([&] { plain->LoadMap(SourceDir() + "/worlds/office.yaml"); }, StatusCode::UNAVAILABLE,
                        "cannot reach navd"));
  EXPECT_EQ(stack.client().GetMap(true).info().name(), "warehouse");
}

TEST(GrpcSecurity, NavdRefusesPlainTextBeyondLoopbackAndOpenTokenFiles) {
  const std::string domain = std::to_string(ReserveDomain());
  CommandResult r = RunCommand({NavdBinary(), "--domain", domain, "--listen", "0.0.0.0:0"}, 20.0);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.output,
            "navd: refusing to listen on 0.0.0.0:0 in plain text: give --tls-cert and --tls-key, or --insecure to let "
            "anyone who reaches the port drive the robot\n");

  const Keystore keys;
  ASSERT_EQ(::chmod(keys.tokens().c_str(), 0640), 0);
  r = RunCommand({NavdBinary(), "--domain", domain, "--listen", "127.0.0.1:0", "--tls-cert", keys.tls("navd.pem"),
                  "--tls-key", keys.tls("navd.key"), "--auth-tokens", keys.tokens()},
                 20.0);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.output, "navd: auth tokens file " + keys.tokens() +
                          " is open to group or others (mode 0640); chmod 600 " + keys.tokens() + "\n");

  // Said explicitly, plain text beyond loopback starts, with a warning.
  const std::string dir = MakeTempDir();
  Process navd({NavdBinary(), "--domain", domain, "--listen", "0.0.0.0:0", "--insecure", "--port-file", dir + "/port"},
               dir + "/navd.log");
  Client plain(ClientOptions{"127.0.0.1:" + WaitForPortFile(dir + "/port", navd, 20.0), 5.0});
  EXPECT_NO_THROW(plain.ListPlanners());
  EXPECT_NE(navd.Log().find("--insecure: gRPC in plain text on 0.0.0.0:0, without authentication"), std::string::npos)
      << navd.Log();
}

TEST(GrpcSecurity, SighupReloadsTheTokensAndABadFileKeepsThePreviousOnes) {
  const Keystore keys;
  StackOptions o = SecuredStack(keys, false);
  o.start_sim = false;
  NavdStack stack(o);
  const std::string navctl_prefix = NavctlBinary() + " --server " + stack.address() + " --tls-ca " + keys.tls("ca.pem");

  // navctl: the token from NAVD_TOKEN or --token; a refusal is one line and a non-zero exit.
  CommandResult r =
      RunCommand({"/bin/bash", "-c", "NAVD_TOKEN=" + keys.token("viewer") + " " + navctl_prefix + " planners"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = RunCommand({"/bin/bash", "-c", navctl_prefix + " --token " + keys.token("viewer") + " navigate --to 3,4"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.output, "navctl: NavigationService.NavigateTo needs the operator role; the caller's role is viewer\n");
  r = RunCommand({"/bin/bash", "-c", navctl_prefix + " planners"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("navctl: PlanningService.ListPlanners needs credentials"), std::string::npos) << r.output;

  const std::string fresh(40, 'a');
  WriteFileAtomically(keys.tokens(), fresh + " viewer\n" + keys.token("admin") + " admin\n");
  ASSERT_EQ(::chmod(keys.tokens().c_str(), 0600), 0);
  ClientOptions with_fresh = keys.Client("");
  with_fresh.token = fresh;
  const auto newcomer = stack.MakeClient(with_fresh);
  EXPECT_TRUE(FailsWith([&] { newcomer->ListPlanners(); }, StatusCode::UNAUTHENTICATED, "ListPlanners"));
  ASSERT_EQ(::kill(stack.navd().pid(), SIGHUP), 0);
  EXPECT_TRUE(WaitUntil(
      [&] {
        try {
          newcomer->ListPlanners();
          return true;
        } catch (const ClientError&) {
          return false;
        }
      },
      10.0))
      << stack.Logs();
  const auto old_viewer = stack.MakeClient(keys.Client("viewer"));
  EXPECT_TRUE(FailsWith([&] { old_viewer->ListPlanners(); }, StatusCode::UNAUTHENTICATED, "ListPlanners"));

  // A broken file is refused and the table in force stays.
  WriteFileAtomically(keys.tokens(), fresh + " root\n");
  ASSERT_EQ(::chmod(keys.tokens().c_str(), 0600), 0);
  ASSERT_EQ(::kill(stack.navd().pid(), SIGHUP), 0);
  EXPECT_TRUE(
      WaitUntil([&] { return stack.navd().Log().find("kept the previous credentials") != std::string::npos; }, 10.0))
      << stack.Logs();
  EXPECT_NO_THROW(newcomer->ListPlanners());
  EXPECT_EQ(stack.navd().Log().find(fresh), std::string::npos) << "navd logged a token";
}

}  // namespace
}  // namespace navd::testing
