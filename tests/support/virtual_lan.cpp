#include "tests/support/virtual_lan.h"

#include <unistd.h>

#include <atomic>
#include <stdexcept>

#include "tests/support/process.h"

namespace navd::testing {
namespace {

const char* kIp = "/usr/sbin/ip";

void Ip(const std::vector<std::string>& args) {
  std::vector<std::string> argv{kIp};
  argv.insert(argv.end(), args.begin(), args.end());
  const CommandResult r = RunCommand(argv, 20.0);
  if (r.exit_code != 0) {
    std::string line;
    for (const auto& a : argv) line += a + " ";
    throw std::runtime_error("virtual LAN: '" + line + "' failed: " + r.output);
  }
}

}  // namespace

std::string VirtualLan::Unavailable() {
  if (geteuid() != 0) return "needs root to create network namespaces (ip netns); CI runs as root";
  if (access(kIp, X_OK) != 0) return std::string("needs ") + kIp + " (Debian's iproute2)";
  return "";
}

std::string VirtualLan::Address(int i) { return "10.77.0." + std::to_string(i + 1); }

VirtualLan::VirtualLan(int hosts) {
  static std::atomic<int> counter{0};
  // Interface names are at most 15 characters; namespace names carry the pid so parallel tests
  // never meet.
  const std::string tag = std::to_string(getpid()) + "n" + std::to_string(counter++);
  bridge_ns_ = "navd-" + tag + "-br";
  Ip({"netns", "add", bridge_ns_});
  try {
    Ip({"-n", bridge_ns_, "link", "add", "br0", "type", "bridge"});
    Ip({"-n", bridge_ns_, "link", "set", "br0", "up"});
    for (int i = 0; i < hosts; ++i) {
      const std::string ns = "navd-" + tag + "-h" + std::to_string(i);
      Ip({"netns", "add", ns});
      hosts_.push_back(ns);
      const std::string port = "v" + tag + "h" + std::to_string(i);
      Ip({"-n", bridge_ns_, "link", "add", port, "type", "veth", "peer", "name", "eth0", "netns", ns});
      Ip({"-n", bridge_ns_, "link", "set", port, "master", "br0", "up"});
      Ip({"-n", ns, "addr", "add", Address(i) + "/24", "dev", "eth0"});
      Ip({"-n", ns, "link", "set", "eth0", "multicast", "off"});
      Ip({"-n", ns, "link", "set", "eth0", "up"});
      Ip({"-n", ns, "link", "set", "lo", "up"});
    }
  } catch (...) {
    Remove();
    throw;
  }
}

VirtualLan::~VirtualLan() { Remove(); }

void VirtualLan::Remove() {
  for (const std::string& ns : hosts_) RunCommand({kIp, "netns", "del", ns}, 20.0);
  hosts_.clear();
  if (!bridge_ns_.empty()) RunCommand({kIp, "netns", "del", bridge_ns_}, 20.0);
  bridge_ns_.clear();
}

std::vector<std::string> VirtualLan::On(int i, std::vector<std::string> argv) const {
  std::vector<std::string> wrapped{kIp, "netns", "exec", hosts_.at(i)};
  wrapped.insert(wrapped.end(), argv.begin(), argv.end());
  return wrapped;
}

}  // namespace navd::testing
