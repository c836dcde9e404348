// No Docker engine runs here, so the deployment files are kept honest by checking that every
// source path they COPY exists in the repository, every binary they name is built by this tree,
// and the compose file runs the images the Dockerfile builds.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "tests/support/navd_fixture.h"

namespace navd::testing {
namespace {

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(Deploy, DockerfileCopiesExistingPathsAndNamesBuiltBinaries) {
  const std::string root = SourceDir();
  const std::string dockerfile = Read(root + "/deploy/Dockerfile");
  ASSERT_FALSE(dockerfile.empty());
  EXPECT_NE(dockerfile.find("FROM debian:bookworm"), std::string::npos);
  // Build-context COPYs (not --from=stage) must name files of the repository.
  const std::regex copy(R"(^COPY\s+(?!--from)(.+)\s+(\S+)\s*$)");
  std::istringstream lines(dockerfile);
  std::string line;
  int copies = 0;
  while (std::getline(lines, line)) {
    std::smatch m;
    if (!std::regex_match(line, m, copy)) continue;
    std::istringstream sources(m[1].str());
    std::string src;
    while (sources >> src) {
      if (src.rfind("--", 0) == 0) continue;
      ++copies;
      EXPECT_TRUE(std::filesystem::exists(root + "/" + src)) << "Dockerfile copies missing path " << src;
    }
  }
  EXPECT_GT(copies, 0);
  // Binaries copied out of the build stage must be ones this build makes, at those build paths.
  const std::regex from_build(R"(COPY --from=build /src/build/(\S+) )");
  int binaries = 0;
  for (std::sregex_iterator it(dockerfile.begin(), dockerfile.end(), from_build), end; it != end; ++it) {
    ++binaries;
    EXPECT_TRUE(std::filesystem::exists(std::string(NAVD_BUILD_DIR) + "/" + (*it)[1].str()))
        << "Dockerfile names a binary this build does not make: " << (*it)[1].str();
  }
  EXPECT_GE(binaries, 3);  // navd, navsim, navctl
}

// The image builds with tests off, so every other folder the top-level CMakeLists adds must be
// copied into the build stage.
TEST(Deploy, DockerfileCopiesEverySourceFolderTheBuildNeeds) {
  const std::string root = SourceDir();
  const std::string dockerfile = Read(root + "/deploy/Dockerfile");
  const std::string cmake = Read(root + "/CMakeLists.txt");
  const std::regex subdir(R"(add_subdirectory\((\w+)\))");
  int folders = 0;
  for (std::sregex_iterator it(cmake.begin(), cmake.end(), subdir), end; it != end; ++it) {
    const std::string folder = (*it)[1].str();
    if (folder == "tests") continue;
    ++folders;
    EXPECT_NE(dockerfile.find("COPY " + folder + " " + folder), std::string::npos)
        << "deploy/Dockerfile does not copy " << folder << "/";
  }
  EXPECT_GE(folders, 7);
}

TEST(Deploy, ComposeRunsBothDaemonsFromTheDockerfile) {
  const std::string root = SourceDir();
  const std::string compose = Read(root + "/deploy/compose.yaml");
  ASSERT_FALSE(compose.empty());
  EXPECT_NE(compose.find("dockerfile: deploy/Dockerfile"), std::string::npos);
  for (const char* binary : {"navd", "navsim"}) {
    EXPECT_NE(compose.find(std::string("\"") + binary + "\""), std::string::npos) << binary;
    EXPECT_TRUE(std::filesystem::exists(std::string(NAVD_BUILD_DIR) + (std::string(binary) == "navd" ? "/server/navd" : "/simulator/navsim")));
  }
  // Containers talk over a real network, so they must opt out of loopback-only DDS and listen
  // beyond 127.0.0.1.
  EXPECT_NE(compose.find("--dds-network"), std::string::npos);
  EXPECT_NE(compose.find("0.0.0.0:50051"), std::string::npos);
  const std::regex context(R"(context:\s*(\S+))");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(compose, m, context));
  EXPECT_TRUE(std::filesystem::exists(root + "/deploy/" + m[1].str()));
}

}  // namespace
}  // namespace navd::testing
