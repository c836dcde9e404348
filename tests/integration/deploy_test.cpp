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

#include <yaml-cpp/yaml.h>

#include "tests/support/keystore.h"
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
                                   << ::testing::PrintToString(loaded.count("?") ? loaded.at("?")
                                                                                 : std::set<std::string>{});
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
    EXPECT_TRUE(std::filesystem::exists(std::string(NAVD_BUILD_DIR) +
                                        (std::string(binary) == "navd" ? "/server/navd" : "/simulator/navsim")));
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

// --- deploy/k8s ------------------------------------------------------------------------------

// The --help text of each program the manifests run, by the name the image knows it by.
class HelpTexts {
 public:
  const std::string* Of(const std::string& program) {
    static const std::map<std::string, std::vector<std::string>> kHelp{
        {"navd", {NavdBinary(), "--help"}},
        {"navsim", {NavsimBinary(), "--help"}},
        {"navctl", {NavctlBinary(), "--help"}},
        {"fast-discovery-server", {"/usr/bin/fast-discovery-server", "-h"}}};
    const auto it = kHelp.find(program);
    if (it == kHelp.end()) return nullptr;
    auto [cached, fresh] = texts_.try_emplace(program);
    if (fresh) cached->second = RunCommand(it->second, 20.0).output;
    return &cached->second;
  }

 private:
  std::map<std::string, std::string> texts_;
};

bool HelpNames(const std::string& help, const std::string& flag) {
  const std::regex word("(^|[\\s,])" + std::regex_replace(flag, std::regex("[-]"), "\\-") + "([\\s,=]|$)");
  return std::regex_search(help, word);
}

std::vector<std::string> Strings(const YAML::Node& list) {
  std::vector<std::string> out;
  for (const auto& n : list) out.push_back(n.as<std::string>());
  return out;
}

// "--flag value" pairs of a command line (a flag followed by another flag has no value).
std::map<std::string, std::string> FlagValues(const std::vector<std::string>& argv) {
  std::map<std::string, std::string> values;
  for (size_t i = 1; i + 1 < argv.size(); ++i) {
    if (argv[i].rfind('-', 0) == 0 && argv[i + 1].rfind('-', 0) != 0) values[argv[i]] = argv[i + 1];
  }
  return values;
}

int PortOf(const std::string& host_port) { return std::stoi(host_port.substr(host_port.rfind(':') + 1)); }

bool Selects(const YAML::Node& selector, const YAML::Node& labels) {
  for (const auto& kv : selector) {
    if (!labels[kv.first.as<std::string>()] ||
        labels[kv.first.as<std::string>()].as<std::string>() != kv.second.as<std::string>())
      return false;
  }
  return selector.size() > 0;
}

TEST(Deploy, KubernetesManifestsAgreeWithThePrograms) {
  const std::string dir = SourceDir() + "/deploy/k8s";
  const YAML::Node kustomization = YAML::LoadFile(dir + "/kustomization.yaml");
  // Generated ConfigMaps and Secrets: name -> keys, each from a file deploy/k8s/prepare writes.
  const Keystore keys;
  const std::string prepare = Read(dir + "/prepare");
  std::map<std::string, std::set<std::string>> generated;
  for (const char* kind : {"configMapGenerator", "secretGenerator"}) {
    for (const auto& g : kustomization[kind]) {
      for (const std::string& entry : Strings(g["files"])) {
        const size_t eq = entry.find('=');
        const std::string key = entry.substr(0, eq), file = entry.substr(eq + 1);
        generated[g["name"].as<std::string>()].insert(key);
        if (file.rfind("files/keys/", 0) == 0) {
          EXPECT_TRUE(std::filesystem::exists(keys.dir() + "/" + file.substr(11)))
              << file << " is not a file scripts/make-keystore makes";
        } else {
          EXPECT_NE(prepare.find("$files/" + file.substr(6)), std::string::npos)
              << file << " is not written by prepare";
        }
      }
    }
  }
  ASSERT_GE(generated.size(), 4u);

  std::vector<YAML::Node> docs;
  for (const std::string& resource : Strings(kustomization["resources"])) {
    for (const YAML::Node& d : YAML::LoadAllFromFile(dir + "/" + resource)) docs.push_back(d);
  }
  std::vector<YAML::Node> services, deployments;
  for (const YAML::Node& d : docs) {
    if (d["kind"].as<std::string>() == "Service") services.push_back(d);
    if (d["kind"].as<std::string>() == "Deployment") deployments.push_back(d);
  }
  ASSERT_GE(deployments.size(), 3u);  // discovery server, navsim, navd

  HelpTexts help;
  std::map<std::string, int> navd_namespaces, navsim_namespaces;
  int navd_containers = 0, probes = 0;
  for (const YAML::Node& deployment : deployments) {
    const std::string name = deployment["metadata"]["name"].as<std::string>();
    const YAML::Node pod = deployment["spec"]["template"];
    const YAML::Node spec = pod["spec"];
    EXPECT_TRUE(Selects(deployment["spec"]["selector"]["matchLabels"], pod["metadata"]["labels"])) << name;
    std::map<std::string, YAML::Node> volumes;
    for (const YAML::Node& v : spec["volumes"]) volumes[v["name"].as<std::string>()] = v;
    std::vector<std::string> init_commands;
    for (const auto& c : spec["initContainers"]) {
      for (const std::string& a : Strings(c["command"])) init_commands.push_back(a);
    }

    const auto check_container = [&](const YAML::Node& c, bool init) {
      const std::string where = name + "/" + c["name"].as<std::string>();
      EXPECT_TRUE(c["resources"]["requests"]["cpu"] && c["resources"]["requests"]["memory"])
          << where << " lacks requests";
      // Each file a flag names is mounted, from a generated key or a file an init container writes.
      const auto check_files = [&](const std::vector<std::string>& argv) {
        for (size_t i = 1; i < argv.size(); ++i) {
          const std::string& a = argv[i];
          if (a.rfind('/', 0) != 0) continue;
          std::string mount;
          size_t best = 0;
          for (const auto& m : c["volumeMounts"]) {
            const std::string path = m["mountPath"].as<std::string>() + "/";
            if (a.rfind(path, 0) == 0 && path.size() > best) {
              best = path.size();
              mount = m["name"].as<std::string>();
            }
          }
          if (mount.empty()) {
            ADD_FAILURE() << where << ": " << a << " is on no mounted volume";
            continue;
          }
          const YAML::Node volume = volumes[mount];
          const std::string key = a.substr(best);
          if (volume["configMap"] || volume["secret"]) {
            const std::string source = volume["configMap"] ? volume["configMap"]["name"].as<std::string>()
                                                           : volume["secret"]["secretName"].as<std::string>();
            EXPECT_TRUE(generated[source].count(key))
                << where << ": " << a << " is not key '" << key << "' of " << source;
          } else if (volume["emptyDir"] && !init) {
            EXPECT_NE(std::find(init_commands.begin(), init_commands.end(), a), init_commands.end())
                << where << ": no init container writes " << a;
          }
        }
      };
      // Each flag exists in the program's --help.
      const auto check_flags = [&](const std::vector<std::string>& argv) {
        const std::string* text = help.Of(argv.at(0));
        if (!text) return;  // coreutils in an init container
        for (const std::string& a : argv) {
          if (a.rfind('-', 0) == 0) {
            EXPECT_TRUE(HelpNames(*text, a)) << where << ": " << argv[0] << " has no option " << a;
          }
        }
      };
      const std::vector<std::string> command = Strings(c["command"]);
      ASSERT_FALSE(command.empty()) << where;
      EXPECT_TRUE(init || help.Of(command[0])) << where << " runs " << command[0];
      check_flags(command);
      check_files(command);
      const auto flags = FlagValues(command);
      if (command[0] == "navd" || command[0] == "navsim") {
        (command[0] == "navd" ? navd_namespaces
                              : navsim_namespaces)[flags.count("--namespace") ? flags.at("--namespace") : ""]++;
      }
      if (flags.count("--dds-discovery-server")) {
        const std::string server = flags.at("--dds-discovery-server");
        const std::string host = server.substr(0, server.rfind(':'));
        const int port = PortOf(server);
        bool found = false;
        for (const YAML::Node& s : services) {
          if (s["metadata"]["name"].as<std::string>() != host) continue;
          for (const auto& p : s["spec"]["ports"]) {
            if (p["port"].as<int>() != port || p["protocol"].as<std::string>() != "UDP") continue;
            for (const YAML::Node& d : deployments) {
              if (!Selects(s["spec"]["selector"], d["spec"]["template"]["metadata"]["labels"])) continue;
              for (const auto& dc : d["spec"]["template"]["spec"]["containers"]) {
                const auto dflags = FlagValues(Strings(dc["command"]));
                found |= dflags.count("-p") && std::stoi(dflags.at("-p")) == p["targetPort"].as<int>();
              }
            }
          }
        }
        EXPECT_TRUE(found) << where << ": no UDP Service " << host << ":" << port
                           << " leads to a discovery server listening on its target port";
      }
      if (command[0] == "navd") {
        ++navd_containers;
        const int listen = PortOf(flags.at("--listen"));
        bool exposed = false;
        for (const auto& p : c["ports"]) exposed |= p["containerPort"].as<int>() == listen;
        EXPECT_TRUE(exposed) << where << " does not expose its --listen port " << listen;
        bool served = false;
        for (const YAML::Node& s : services) {
          if (!Selects(s["spec"]["selector"], pod["metadata"]["labels"])) continue;
          for (const auto& p : s["spec"]["ports"]) served |= p["targetPort"].as<int>() == listen;
        }
        EXPECT_TRUE(served) << where << ": no Service targets port " << listen;
        for (const char* probe : {"readinessProbe", "livenessProbe"}) {
          const std::vector<std::string> argv = Strings(c[probe]["exec"]["command"]);
          ASSERT_GE(argv.size(), 2u) << where << " lacks a " << probe;
          ++probes;
          EXPECT_EQ(argv.front(), "navctl") << where << " " << probe;
          EXPECT_EQ(argv.back(), "health") << where << " " << probe << " is not grpc.health.v1";
          check_flags(argv);
          check_files(argv);
          EXPECT_EQ(PortOf(FlagValues(argv).at("--server")), listen) << where << " " << probe;
        }
      }
    };
    for (const YAML::Node& c : spec["initContainers"]) check_container(c, true);
    for (const YAML::Node& c : spec["containers"]) check_container(c, false);
  }
  EXPECT_GE(navd_containers, 1);
  EXPECT_GE(probes, 2);
  EXPECT_EQ(navd_namespaces, navsim_namespaces) << "every robot's navd needs its navsim in the same topic namespace";
}

}  // namespace
}  // namespace navd::testing
