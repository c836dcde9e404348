// The live view of navd and navsim, judged by clients that are not ours: Foxglove's own
// @foxglove/ws-protocol client (Node.js) and Debian's chromium driven by playwright-core, against
// real navsim and navd processes. The Node scripts live in tests/view (npm ci there installs their
// packages; scripts/install-deps does it).
#include <gtest/gtest.h>

#include <cstdlib>
#include <utility>

#include "tests/support/keystore.h"
#include "tests/support/navd_fixture.h"

namespace navd::testing {
namespace {

// navsim and navd, each with its view on a free port; the ports are read from their port files.
struct ViewStack {
  std::string dir = MakeTempDir();
  std::unique_ptr<NavdStack> stack;
  std::string navd_view, navsim_view;

  explicit ViewStack(std::vector<std::string> navd_args = {}, ClientOptions client = {}) {
    StackOptions o;
    o.client = std::move(client);
    o.rate = 2.0;
    o.lockstep = false;
    o.navd_args = {"--view", "127.0.0.1:0", "--view-port-file", dir + "/navd-view.port"};
    o.navd_args.insert(o.navd_args.end(), navd_args.begin(), navd_args.end());
    o.sim_args = {"--view", "127.0.0.1:0", "--view-port-file", dir + "/navsim-view.port"};
    stack = std::make_unique<NavdStack>(o);
    navd_view = WaitForPortFile(dir + "/navd-view.port", stack->navd(), 10.0);
    navsim_view = WaitForPortFile(dir + "/navsim-view.port", *stack->sim(), 10.0);
  }
};

std::string Script(const std::string& name) { return SourceDir() + "/tests/view/" + name; }

TEST(LiveView, FoxgloveClientListsTheChannelsAndDecodesMapAndPoseWithTheirSchemas) {
  ViewStack v;
  ASSERT_TRUE(v.stack->WaitForPose(20.0)) << v.stack->Logs();
  const auto r = RunCommand(
      {"/usr/bin/env", "node", Script("foxglove_client_test.mjs"), v.navd_view, NavctlBinary(), v.stack->address()},
      90.0);
  EXPECT_EQ(r.exit_code, 0) << r.output << v.stack->Logs();
  EXPECT_NE(r.output.find("PASS"), std::string::npos) << r.output;
}

// NAVD_VIEW_SCREENSHOTS=DIR keeps the screenshots there (else in the test's temporary folder).
TEST(LiveView, BrowserDrawsTheRobotWhereNavdSaysClicksAGoalAndCancelsIt) {
  ViewStack v;
  ASSERT_TRUE(v.stack->WaitForPose(20.0)) << v.stack->Logs();
  const char* keep = std::getenv("NAVD_VIEW_SCREENSHOTS");
  const std::string shots = keep ? keep : v.dir;
  const auto r = RunCommand({"/usr/bin/env", "node", Script("browser_test.mjs"), v.navd_view, v.navsim_view,
                             NavctlBinary(), v.stack->address(), shots},
                            180.0);
  EXPECT_EQ(r.exit_code, 0) << r.output << v.stack->Logs();
  EXPECT_NE(r.output.find("PASS"), std::string::npos) << r.output;
}

// With --auth-tokens the view takes the same tokens: none is HTTP 401, a viewer watches, an
// operator drives.
TEST(LiveView, TokensDecideWhoWatchesAndWhoSendsGoals) {
  const Keystore keys;
  ViewStack v({"--tls-cert", keys.tls("navd.pem"), "--tls-key", keys.tls("navd.key"), "--auth-tokens", keys.tokens()},
              keys.Client("admin"));
  ASSERT_TRUE(v.stack->WaitForPose(20.0)) << v.stack->Logs();
  const auto r = RunCommand(
      {"/usr/bin/env", "node", Script("access_test.mjs"), v.navd_view, keys.token("viewer"), keys.token("operator")},
      90.0);
  EXPECT_EQ(r.exit_code, 0) << r.output << v.stack->Logs();
  EXPECT_NE(r.output.find("PASS"), std::string::npos) << r.output;
}

TEST(LiveView, BadViewAddressesAreOneLineErrors) {
  const auto bad = RunCommand({NavdBinary(), "--view", "nonsense", "--listen", "127.0.0.1:0"}, 20.0);
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("--view: 'nonsense' is not HOST:PORT"), std::string::npos) << bad.output;
  const auto far = RunCommand({NavdBinary(), "--view", "0.0.0.0:0", "--listen", "127.0.0.1:0"}, 20.0);
  EXPECT_EQ(far.exit_code, 2) << far.output;
  EXPECT_NE(far.output.find("beyond loopback"), std::string::npos) << far.output;
}

}  // namespace
}  // namespace navd::testing
