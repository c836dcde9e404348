// Book chapter 7 end to end: navd --people-aware drives down navsim's pedestrian street
// (worlds/scenarios/street.yaml: 10-40 people who walk at 1.3 m/s and do not look out for the
// robot), tracking the people its laser sees and steering with the crowd RRT; navctl judges the
// run against navsim's truth (personal-zone share, collisions). navsim + navd + navctl over
// loopback. The 50-run figures come from scripts/street-runs.
#include <gtest/gtest.h>

#include <cstdlib>
#include <nlohmann/json.hpp>

#include "tests/support/navd_fixture.h"

namespace navd::testing {
namespace {

TEST(StreetE2E, PeopleAwareNavigationDrivesDownTheStreetOutOfPeoplesWay) {
  const std::string scenario = SourceDir() + "/worlds/scenarios/street.yaml";
  StackOptions options;
  options.rate = 10.0;
  options.sim_args = {"--scenario", scenario, "--seed", "3"};
  options.navd_args = {"--world", SourceDir() + "/worlds/street.yaml", "--people-aware"};
  // navd's debug log has each crowd plan and the nearest person it knew (inherited by the child).
  setenv("SPDLOG_LEVEL", "debug", 1);
  NavdStack stack(options);
  ASSERT_TRUE(stack.WaitForPose(20.0)) << stack.Logs();
  // 45 m towards the far end of the street (the mission ends there, succeeded).
  const auto run = RunCommand({NavctlBinary(), "--server", stack.address(), "follow", "--waypoints", "99,4",
                               "--max-distance", "45", "--measure", "--domain", std::to_string(stack.domain()),
                               "--json", "--timeout", "200"},
                              230.0);
  const std::string logs = stack.Logs();
  ASSERT_NE(run.output.find('{'), std::string::npos) << run.output << logs;
  const auto j = nlohmann::json::parse(run.output.substr(run.output.find('{')));
  const auto& truth = j.at("truth");
  ASSERT_TRUE(truth.contains("people")) << run.output;
  const auto& people = truth.at("people");
  const double outside = people.at("outside_personal_zone").get<double>();
  const double sim_time = truth.at("sim_time").get<double>();
  const double distance = truth.at("distance_travelled").get<double>();
  std::printf("street: %.1f m in %.1f s of simulated time, nearest person outside the personal zone %.1f%% of the "
              "time, outside the intimate zone %.1f%%, closest %.2f m, collisions %d\n",
              distance, sim_time, 100.0 * outside, 100.0 * people.at("outside_intimate_zone").get<double>(),
              people.at("nearest").get<double>(), truth.at("collisions").get<int>());
  EXPECT_EQ(run.exit_code, 0) << run.output << logs;
  EXPECT_GE(distance, 40.0);
  // At speed among the crowd: on average at least 0.8 m/s (the desired speed is 1.5 m/s).
  EXPECT_LT(sim_time, 45.0 / 0.8);
  EXPECT_GT(people.at("time").get<double>(), 0.9 * sim_time) << "people all along the street";
  // One run is one crowd, and runs vary widely (the same seed gave 59.5 % and 81.6 %: DDS timing
  // changes who meets whom; 68-98 % over 25 seeds): this bounds a single run, street-runs measures.
  EXPECT_GE(outside, 0.5) << logs;
  EXPECT_NE(logs.find("crowd plan"), std::string::npos) << "no crowd plan in navd's debug log";
  EXPECT_NE(logs.find(": driving "), std::string::npos);
}

}  // namespace
}  // namespace navd::testing
