#pragma once
// The credentials scripts/make-keystore makes (the script users run), in a fresh temporary
// directory, with accessors for what tests hand to navd, navsim and clients.
#include <string>
#include <vector>

#include "client_lib/navd_client.h"

namespace navd::testing {

class Keystore {
 public:
  // `hosts`: names or addresses navd's certificate carries beside localhost and 127.0.0.1.
  explicit Keystore(const std::vector<std::string>& hosts = {});

  const std::string& dir() const { return dir_; }
  std::string tls(const std::string& file) const { return dir_ + "/tls/" + file; }
  std::string tokens() const { return dir_ + "/tokens"; }
  // The bearer token of `role` (viewer, operator, admin).
  std::string token(const std::string& role) const;
  // The DDS Security enclave of `name` (navd, navsim, navctl).
  std::string enclave(const std::string& name) const { return dir_ + "/dds/enclaves/" + name; }

  // TLS trusting the keystore's CA, with the token of `token_role` (none when empty) and, for
  // mutual TLS, the client certificate `cert` + ".pem" / ".key".
  ClientOptions Client(const std::string& token_role, const std::string& cert = "") const;

  // A client certificate with common name `cn` at dir()/name.{pem,key}, signed by the keystore's
  // CA or, when `foreign`, by a CA of its own; valid for `days` (negative: already expired).
  // Returns dir()/name.
  std::string ExtraClientCertificate(const std::string& name, const std::string& cn, bool foreign, int days) const;

 private:
  std::string dir_;
};

}  // namespace navd::testing
