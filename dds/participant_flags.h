#pragma once
// The command-line flags of a DDS participant, shared by navd and navsim so that both take the same
// names the same way. Header-only: only the programs' command lines include CLI11.
#include <CLI/CLI.hpp>
#include <string>

#include "dds/participant.h"

namespace navd::dds {

// Adds --domain, --dds-network, --dds-peer, --dds-discovery-server and --dds-security to `app`,
// filling `options`. --dds-network lands in `network` ("loopback" by default), for ParseNetwork
// after parsing, whose refusal names the value.
inline void AddParticipantFlags(CLI::App& app, ParticipantOptions& options, std::string& network) {
  app.add_option("--domain", options.domain, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--dds-network", network, "loopback (default: 127.0.0.1 only) or all (every interface)");
  app.add_option("--dds-peer", options.peers, "Extra unicast DDS discovery peer (IPv4), repeatable");
  app.add_option("--dds-discovery-server", options.discovery_server,
                 "HOST:PORT of a Fast DDS discovery server (fast-discovery-server -i 0): discover peers through it "
                 "by unicast, as in a cluster without multicast");
  app.add_option("--dds-security", options.security_enclave,
                 "DDS Security enclave directory (cert.pem, key.pem, CAs, signed governance and permissions; "
                 "scripts/make-keystore makes one): authenticated, access-controlled, encrypted DDS");
}

}  // namespace navd::dds
