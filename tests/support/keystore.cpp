#include "tests/support/keystore.h"

#include <stdexcept>

#include "services/common/text_file.h"
#include "tests/support/navd_fixture.h"
#include "tests/support/process.h"

namespace navd::testing {

Keystore::Keystore(const std::vector<std::string>& hosts) : dir_(MakeTempDir() + "/keys") {
  std::vector<std::string> argv{SourceDir() + "/scripts/make-keystore", dir_};
  for (const std::string& h : hosts) argv.insert(argv.end(), {"--host", h});
  const CommandResult r = RunCommand(argv);
  if (r.exit_code != 0) throw std::runtime_error("make-keystore failed: " + r.output);
}

std::string Keystore::token(const std::string& role) const {
  std::string s = ReadTextFile(dir_ + "/token." + role, "token");
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

ClientOptions Keystore::Client(const std::string& token_role, const std::string& cert) const {
  ClientOptions o;
  o.timeout = 5.0;
  o.tls_ca = tls("ca.pem");
  if (!token_role.empty()) o.token = token(token_role);
  if (!cert.empty()) {
    o.tls_cert = cert + ".pem";
    o.tls_key = cert + ".key";
  }
  return o;
}

std::string Keystore::ExtraClientCertificate(const std::string& name, const std::string& cn, bool foreign,
                                             int days) const {
  std::string base = dir_ + "/" + name;
  std::string script = "set -e; cd " + dir_ + "; openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:P-256 -out " +
                       base + ".key; openssl req -new -key " + base + ".key -subj /CN=" + cn + " -out " + base +
                       ".csr;";
  std::string ca = tls("ca.pem"), ca_key = tls("ca.key");
  if (foreign) {
    ca = base + "-ca.pem";
    ca_key = base + "-ca.key";
    script += "openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:P-256 -nodes -keyout " + ca_key + " -out " + ca +
              " -days 30 -subj /CN=intruder-ca;";
  }
  script += "printf 'extendedKeyUsage=clientAuth\\n' > " + base + ".ext; openssl x509 -req -in " + base + ".csr -CA " +
            ca + " -CAkey " + ca_key + " -CAcreateserial -days " + std::to_string(days) + " -extfile " + base +
            ".ext -out " + base + ".pem";
  const CommandResult r = RunCommand({"/bin/bash", "-c", script + " 2>&1"});
  if (r.exit_code != 0) throw std::runtime_error("openssl failed: " + r.output);
  return base;
}

}  // namespace navd::testing
