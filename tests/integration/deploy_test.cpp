// No Docker engine runs here, so the deployment files are kept honest by checking that every
// source path they COPY exists in the repository, every binary they name is built by this tree,
// the runtime stage installs the packages the binaries load, and the compose file runs the images
// the Dockerfile builds. scripts/image-smoke builds that runtime stage without Docker and runs it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
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

// The packages the runtime stage installs: the words after --no-install-recommends up to "&&".
std::set<std::string> RuntimeStagePackages(const std::string& dockerfile) {
  const size_t stage = dockerfile.find(" AS runtime");
  const std::string marker = "--no-install-recommends";
  const size_t from = dockerfile.find(marker, stage);
  const size_t to = dockerfile.find("&&", from);
  if (stage == std::string::npos || from == std::string::npos || to == std::string::npos) return {};
  std::istringstream words(dockerfile.substr(from + marker.size(), to - from - marker.size()));
  std::set<std::string> packages;
  for (std::string w; words >> w;) {
    if (w != "\\") packages.insert(w);
  }
  return packages;
}

// The Debian package of every shared library the binaries load, from ldd and dpkg; libraries no
// package owns, or that ldd cannot find, come back under "?".
std::map<std::string, std::set<std::string>> PackagesLoadedBy(const std::vector<std::string>& binaries) {
  std::string script = "for b in";
  for (const std::string& b : binaries) script += " '" + b + "'";
  // Debian's merged /usr: ldd may print /lib/... where dpkg registered /usr/lib/..., or back. One
  // dpkg -S call for every candidate path: each call reads dpkg's whole database.
  script += R"sh(; do ldd "$b"; done | awk '$3 ~ /^\// {print $3} /not found/ {print "missing:" $1}' | sort -u > libs
    variants() { echo "$1"; echo "/usr$1"; echo "${1#/usr}"; realpath "$1" 2>/dev/null; }
    dpkg -S $(while read l; do variants "$l"; done < libs | sort -u) 2>/dev/null > owners
    while read l; do p=""
      for c in $(variants "$l"); do
        p=$(awk -F': ' -v c="$c" '$2 == c {print $1; exit}' owners | cut -d: -f1); [ -n "$p" ] && break
      done
      echo "${p:-?} $l"
    done < libs)sh";
  const CommandResult r = RunCommand({"/bin/bash", "-c", "cd " + MakeTempDir() + " && " + script}, 120.0);
  std::map<std::string, std::set<std::string>> packages;
  std::istringstream lines(r.output);
  for (std::string package, library; lines >> package >> library;) packages[package].insert(library);
  return packages;
}

TEST(Deploy, RuntimeStageInstallsExactlyThePackagesTheBinariesLoad) {
  const std::set<std::string> listed = RuntimeStagePackages(Read(SourceDir() + "/deploy/Dockerfile"));
  ASSERT_FALSE(listed.empty()) << "no apt-get install list in the runtime stage of deploy/Dockerfile";
  const auto loaded = PackagesLoadedBy({NavdBinary(), NavsimBinary(), NavctlBinary()});
  ASSERT_GE(loaded.size(), 10u) << "ldd/dpkg found too few packages";
  EXPECT_EQ(loaded.count("?"), 0u) << "libraries no Debian package owns or ldd cannot find: "
                                   << ::testing::PrintToString(loaded.count("?") ? loaded.at("?") : std::set<std::string>{});
  for (const auto& [package, libraries] : loaded) {
    if (package == "?") continue;
    EXPECT_TRUE(listed.count(package)) << "the runtime stage lacks " << package << ", which provides "
                                       << *libraries.begin() << " (add it to deploy/Dockerfile's runtime list)";
  }
  for (const std::string& package : listed) {
    EXPECT_TRUE(loaded.count(package)) << "the runtime stage installs " << package << ", which no binary loads";
  }
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
  // ... so gRPC is TLS with roles, from the keystore the compose file mounts.
  for (const char* flag : {"--tls-cert", "--tls-key", "--auth-tokens"}) {
    EXPECT_NE(compose.find(flag), std::string::npos) << "compose's navd lacks " << flag;
  }
  const std::regex context(R"(context:\s*(\S+))");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(compose, m, context));
  EXPECT_TRUE(std::filesystem::exists(root + "/deploy/" + m[1].str()));
}

}  // namespace
}  // namespace navd::testing
