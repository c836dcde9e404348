#include "dds/security.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace navd::dds {

void AddSecurityProperties(const std::string& enclave_dir, eprosima::fastdds::dds::PropertyPolicyQos& properties) {
  const std::filesystem::path dir = std::filesystem::absolute(enclave_dir);
  const auto file = [&](const char* name) {
    const std::filesystem::path p = dir / name;
    if (!std::ifstream(p).good()) {
      throw std::invalid_argument("DDS security enclave " + enclave_dir + " lacks a readable " + name +
                                  " (scripts/make-keystore makes enclaves)");
    }
    return "file://" + p.string();
  };
  auto& p = properties.properties();
  const std::string auth = "dds.sec.auth.builtin.PKI-DH.";
  const std::string access = "dds.sec.access.builtin.Access-Permissions.";
  p.emplace_back("dds.sec.auth.plugin", "builtin.PKI-DH");
  p.emplace_back(auth + "identity_ca", file("identity_ca.cert.pem"));
  p.emplace_back(auth + "identity_certificate", file("cert.pem"));
  p.emplace_back(auth + "private_key", file("key.pem"));
  p.emplace_back("dds.sec.access.plugin", "builtin.Access-Permissions");
  p.emplace_back(access + "permissions_ca", file("permissions_ca.cert.pem"));
  p.emplace_back(access + "governance", file("governance.p7s"));
  p.emplace_back(access + "permissions", file("permissions.p7s"));
  p.emplace_back("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
}

}  // namespace navd::dds
