#pragma once
// One DDS domain participant with navd's transport policy, plus typed publishers and latest-value
// subscribers. Only transport code (server/, simulator/, client_lib/, tests) includes this.
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace navd::dds {

// Which network the participant may use.
enum class Network {
  // Default: UDPv4 on 127.0.0.1 only, unicast discovery to 127.0.0.1 peers, no multicast and no
  // shared memory, so nothing leaves the host and parallel test domains stay apart.
  kLoopback,
  // UDPv4 on every interface with multicast discovery, for deployments. No shared memory:
  // containers and hosts share none, and Fast DDS would pick it for peers it believes local and
  // then reach nothing. Data sharing stays off in both (see EndpointQos).
  kAll,
};

// Parses "loopback" or "all"; throws std::invalid_argument naming the value otherwise.
Network ParseNetwork(const std::string& s);

struct ParticipantOptions {
  int domain = 0;
  Network network = Network::kLoopback;
  std::string name = "navd";
  // Extra unicast discovery peers (IPv4 addresses) for Network::kAll across hosts.
  std::vector<std::string> peers;
  // DDS Security enclave directory (security.h); empty: no security.
  std::string security_enclave;
  // HOST:PORT of a Fast DDS discovery server (fast-discovery-server -i 0): the participant
  // discovers its peers through it, by unicast, instead of by multicast or initial peers.
  std::string discovery_server;
};

enum class Reliability { kBestEffort, kReliable };

class Participant {
 public:
  explicit Participant(const ParticipantOptions& options);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  // `large`: samples may exceed a UDP datagram (maps): published asynchronously, so Fast DDS
  // fragments them.
  eprosima::fastdds::dds::DataWriter* CreateWriter(const std::string& topic, eprosima::fastdds::dds::TypeSupport type,
                                                   Reliability reliability, int depth, bool large = false);
  eprosima::fastdds::dds::DataReader* CreateReader(const std::string& topic, eprosima::fastdds::dds::TypeSupport type,
                                                   Reliability reliability, int depth,
                                                   eprosima::fastdds::dds::DataReaderListener* listener);
  // Deletes a reader; waits for a listener callback in progress, so the listener may be freed after.
  void DeleteReader(eprosima::fastdds::dds::DataReader* reader);
  void DeleteWriter(eprosima::fastdds::dds::DataWriter* writer);
  int domain() const { return domain_; }

 private:
  eprosima::fastdds::dds::Topic* TopicFor(const std::string& name, eprosima::fastdds::dds::TypeSupport& type);

  int domain_;
  std::mutex mutex_;
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
};

// A typed writer. PubSubType is a fastddsgen-generated type support class.
template <typename PubSubType>
class Writer {
 public:
  using Message = typename PubSubType::type;
  Writer(Participant& participant, const std::string& topic, Reliability reliability, int depth = 10,
         bool large = false)
      : participant_(participant),
        writer_(participant.CreateWriter(topic, eprosima::fastdds::dds::TypeSupport(new PubSubType()), reliability,
                                         depth, large)) {}
  ~Writer() { participant_.DeleteWriter(writer_); }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;
  // False when the sample was not sent. Fast DDS's shared-memory transport locks each reader's
  // port: a peer stopped while holding that lock (SIGSTOP, a debugger) makes the write throw
  // boost's "interprocess mutex timeout" after a while, which killed navsim in the lockstep test
  // that freezes navd. A sample lost to a stuck reader is dropped, as on any lossy link.
  bool Write(const Message& m) {
    try {
      return writer_->write(const_cast<Message*>(&m));
    } catch (const std::exception&) {
      return false;
    }
  }
  // Blocks until every matched reliable reader acknowledged what was written, or `timeout_s`.
  bool WaitForAcknowledgments(double timeout_s) {
    return writer_->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(timeout_s)) == ReturnCode_t::RETCODE_OK;
  }
  // Number of matched readers, for waiting on discovery.
  int matched() const {
    eprosima::fastdds::dds::PublicationMatchedStatus s;
    writer_->get_publication_matched_status(s);
    return s.current_count;
  }

 private:
  Participant& participant_;
  eprosima::fastdds::dds::DataWriter* writer_;
};

// A typed reader that keeps the newest sample (the latest-value slot of the design) and optionally
// calls a callback on DDS's listener thread. Callbacks must be quick: copy and return.
template <typename PubSubType>
class Reader : public eprosima::fastdds::dds::DataReaderListener {
 public:
  using Message = typename PubSubType::type;
  using Callback = std::function<void(const Message&)>;

  Reader(Participant& participant, const std::string& topic, Reliability reliability, Callback callback = {},
         int depth = 10)
      : participant_(participant), callback_(std::move(callback)) {
    reader_ = participant.CreateReader(topic, eprosima::fastdds::dds::TypeSupport(new PubSubType()), reliability, depth,
                                       this);
  }
  // Must go before its Participant. Deleting the reader waits for a running callback.
  ~Reader() override { participant_.DeleteReader(reader_); }
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  std::optional<Message> Latest() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return latest_;
  }
  uint64_t count() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return count_;
  }

  void on_data_available(eprosima::fastdds::dds::DataReader* reader) override {
    Message m;
    eprosima::fastdds::dds::SampleInfo info;
    while (reader->take_next_sample(&m, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        latest_ = m;
        ++count_;
      }
      if (callback_) callback_(m);
    }
  }

 private:
  Participant& participant_;
  Callback callback_;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
  mutable std::mutex mutex_;
  std::optional<Message> latest_;
  uint64_t count_ = 0;
};

}  // namespace navd::dds
