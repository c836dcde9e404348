#pragma once
// Hosts for tests that need more than one machine: network namespaces of this test's own, each
// with an eth0 on one bridge (in a namespace of its own too), addresses 10.77.0.1, .2, ... /24 and
// multicast off, so only unicast crosses. Everything is removed when the object goes. Needs root.
#include <string>
#include <vector>

namespace navd::testing {

class VirtualLan {
 public:
  // Why the LAN cannot be made here (not root, no `ip`), or "" when it can.
  static std::string Unavailable();

  explicit VirtualLan(int hosts);
  ~VirtualLan();
  VirtualLan(const VirtualLan&) = delete;
  VirtualLan& operator=(const VirtualLan&) = delete;

  // The address of host `i` (0-based): 10.77.0.(i + 1).
  static std::string Address(int i);
  // `argv` run inside host `i`'s network namespace.
  std::vector<std::string> On(int i, std::vector<std::string> argv) const;

 private:
  void Remove();

  std::string bridge_ns_;
  std::vector<std::string> hosts_;
};

}  // namespace navd::testing
