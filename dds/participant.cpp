#include "dds/participant.h"

#include <arpa/inet.h>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/rtps/attributes/ServerAttributes.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <netdb.h>

#include <cstdlib>
#include <stdexcept>

#include "dds/security.h"

namespace navd::dds {

using namespace eprosima::fastdds::dds;
using eprosima::fastrtps::rtps::IPLocator;
using eprosima::fastrtps::rtps::Locator_t;

Network ParseNetwork(const std::string& s) {
  if (s == "loopback") return Network::kLoopback;
  if (s == "all") return Network::kAll;
  throw std::invalid_argument("DDS network '" + s + "' is not 'loopback' or 'all'");
}

namespace {

Locator_t UdpLocator(const std::string& address) {
  Locator_t loc;
  loc.kind = LOCATOR_KIND_UDPv4;
  IPLocator::setIPv4(loc, address);
  return loc;
}

// "HOST:PORT", HOST a name or an IPv4 address, as a UDPv4 locator.
Locator_t DiscoveryServerLocator(const std::string& address) {
  const size_t colon = address.rfind(':');
  const auto bad = [&](const std::string& why) {
    return std::invalid_argument("DDS discovery server '" + address + "' " + why);
  };
  if (colon == std::string::npos || colon == 0) throw bad("is not HOST:PORT");
  const std::string host = address.substr(0, colon), port_text = address.substr(colon + 1);
  char* end = nullptr;
  const long port = std::strtol(port_text.c_str(), &end, 10);
  if (port_text.empty() || *end != '\0' || port < 1 || port > 65535) throw bad("has no port in 1..65535");
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  if (getaddrinfo(host.c_str(), nullptr, &hints, &found) != 0 || found == nullptr) {
    throw bad("names no IPv4 host this machine can resolve");
  }
  char ip[INET_ADDRSTRLEN] = {};
  inet_ntop(AF_INET, &reinterpret_cast<sockaddr_in*>(found->ai_addr)->sin_addr, ip, sizeof ip);
  freeaddrinfo(found);
  Locator_t loc = UdpLocator(ip);
  loc.port = static_cast<uint32_t>(port);
  return loc;
}

DomainParticipantQos MakeQos(const ParticipantOptions& o) {
  DomainParticipantQos qos = PARTICIPANT_QOS_DEFAULT;
  qos.name(o.name);
  auto& builtin = qos.wire_protocol().builtin;
  if (o.network == Network::kLoopback) {
    qos.transport().use_builtin_transports = false;
    auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
    udp->interfaceWhiteList.emplace_back("127.0.0.1");
    // Unicast discovery probes ports of this many participant ids per peer; a test domain holds a
    // handful (navsim, navd, the test, navctl), so 32 leaves room.
    udp->maxInitialPeersRange = 32;
    qos.transport().user_transports.push_back(udp);
    const Locator_t lo = UdpLocator("127.0.0.1");
    // Explicit unicast metatraffic locators stop Fast DDS from adding its multicast ones; port 0
    // asks it to fill in the well-known port for this domain and participant id.
    builtin.metatrafficUnicastLocatorList.push_back(lo);
    qos.wire_protocol().default_unicast_locator_list.push_back(lo);
    builtin.initialPeersList.push_back(lo);
  } else {
    qos.transport().use_builtin_transports = false;
    qos.transport().user_transports.push_back(std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>());
  }
  if (!o.discovery_server.empty()) {
    if (!o.security_enclave.empty()) {
      // Under DDS Security a participant's GUID prefix is derived from its certificate, so the
      // clients' well-known server prefix no longer names the server; Fast DDS 2.9 has no secure
      // discovery server.
      throw std::invalid_argument(
          "a DDS discovery server cannot be used with DDS Security in Fast DDS 2.9: give unicast peers "
          "(--dds-peer) instead");
    }
    eprosima::fastdds::rtps::RemoteServerAttributes server;
    eprosima::fastdds::rtps::get_server_client_default_guidPrefix(0, server.guidPrefix);
    server.metatrafficUnicastLocatorList.push_back(DiscoveryServerLocator(o.discovery_server));
    builtin.discovery_config.discoveryProtocol = eprosima::fastrtps::rtps::DiscoveryProtocol_t::CLIENT;
    builtin.discovery_config.m_DiscoveryServers.push_back(server);
  }
  for (const auto& peer : o.peers) {
    if (!IPLocator::isIPv4(peer)) throw std::invalid_argument("DDS peer '" + peer + "' is not an IPv4 address");
    builtin.initialPeersList.push_back(UdpLocator(peer));
  }
  // Keeps discovery brisk so tests and CLI calls do not wait long for matches.
  builtin.discovery_config.leaseDuration_announcementperiod = eprosima::fastrtps::Duration_t(1, 0);
  builtin.discovery_config.initial_announcements.count = 5;
  builtin.discovery_config.initial_announcements.period = eprosima::fastrtps::Duration_t(0, 100'000'000);
  if (!o.security_enclave.empty()) AddSecurityProperties(o.security_enclave, qos.properties());
  return qos;
}

}  // namespace

Participant::Participant(const ParticipantOptions& options) : domain_(options.domain) {
  if (options.domain < 0 || options.domain > 232) {
    throw std::invalid_argument("DDS domain " + std::to_string(options.domain) + " is outside 0..232");
  }
  participant_ = DomainParticipantFactory::get_instance()->create_participant(options.domain, MakeQos(options));
  if (!participant_)
    throw std::runtime_error("cannot create a DDS participant on domain " + std::to_string(options.domain));
  publisher_ = participant_->create_publisher(PUBLISHER_QOS_DEFAULT);
  subscriber_ = participant_->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
  if (!publisher_ || !subscriber_) throw std::runtime_error("cannot create DDS publisher/subscriber");
}

Participant::~Participant() {
  if (participant_) {
    participant_->delete_contained_entities();
    DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }
}

Topic* Participant::TopicFor(const std::string& name, TypeSupport& type) {
  if (auto it = topics_.find(name); it != topics_.end()) return it->second;
  type.register_type(participant_);
  Topic* topic = participant_->create_topic(name, type.get_type_name(), TOPIC_QOS_DEFAULT);
  if (!topic) throw std::runtime_error("cannot create DDS topic " + name);
  topics_[name] = topic;
  return topic;
}

// Reader and writer QoS share these fields: keep-last history of `depth`, volatile durability, and
// no data sharing. Fast DDS turns data sharing on by itself for fixed-size types between processes
// on one host; in 2.9 its reader side can segfault in the shared history (a navd died that way in
// CI, inside libfastrtps's DataSharing code, and stale segments pile up in /dev/shm when a process
// is killed). Our samples are small and few, so the transport's copy costs nothing that matters.
template <typename Qos>
Qos EndpointQos(Qos qos, Reliability reliability, int depth) {
  qos.reliability().kind =
      reliability == Reliability::kReliable ? RELIABLE_RELIABILITY_QOS : BEST_EFFORT_RELIABILITY_QOS;
  qos.history().kind = KEEP_LAST_HISTORY_QOS;
  qos.history().depth = depth;
  qos.durability().kind = VOLATILE_DURABILITY_QOS;
  qos.data_sharing().off();
  return qos;
}

DataWriter* Participant::CreateWriter(const std::string& topic, TypeSupport type, Reliability reliability, int depth,
                                      bool large) {
  std::lock_guard<std::mutex> lock(mutex_);
  DataWriterQos qos = EndpointQos(DATAWRITER_QOS_DEFAULT, reliability, depth);
  if (large) qos.publish_mode().kind = ASYNCHRONOUS_PUBLISH_MODE;
  DataWriter* w = publisher_->create_datawriter(TopicFor(topic, type), qos);
  if (!w) throw std::runtime_error("cannot create DDS writer on " + topic);
  return w;
}

DataReader* Participant::CreateReader(const std::string& topic, TypeSupport type, Reliability reliability, int depth,
                                      DataReaderListener* listener) {
  std::lock_guard<std::mutex> lock(mutex_);
  const DataReaderQos qos = EndpointQos(DATAREADER_QOS_DEFAULT, reliability, depth);
  DataReader* r = subscriber_->create_datareader(TopicFor(topic, type), qos, listener);
  if (!r) throw std::runtime_error("cannot create DDS reader on " + topic);
  return r;
}

void Participant::DeleteReader(DataReader* reader) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (reader) subscriber_->delete_datareader(reader);
}

void Participant::DeleteWriter(DataWriter* writer) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (writer) publisher_->delete_datawriter(writer);
}

}  // namespace navd::dds
