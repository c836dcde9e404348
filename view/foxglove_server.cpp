// websocketpp 0.8 does not compile as C++20 (template-ids on constructors), so this file, the only
// one that includes it, is built as C++17 (view/CMakeLists.txt).
#include "view/foxglove_server.h"

#include <spdlog/spdlog.h>

#include <atomic>
#include <cctype>
#include <chrono>
#include <deque>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>
#include <utility>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

#include "services/common/error.h"

namespace navd::view {
namespace {

using WsServer = websocketpp::server<websocketpp::config::asio>;
using Json = nlohmann::json;

constexpr const char* kSubprotocol = "foxglove.websocket.v1";
constexpr uint8_t kMessageDataOpcode = 0x01;        // server -> client
constexpr uint8_t kClientMessageDataOpcode = 0x01;  // client -> server
constexpr auto kRetryPeriod = std::chrono::milliseconds(20);

void PutLe(std::string& out, uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>((value >> (8 * i)) & 0xff));
}

uint32_t GetLe32(const std::string& in, size_t at) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(static_cast<uint8_t>(in[at + i])) << (8 * i);
  return v;
}

// The value of `key` in the query string of a request target ("/?token=abc&x=1"), percent-decoded.
std::string QueryValue(const std::string& target, const std::string& key) {
  const size_t q = target.find('?');
  if (q == std::string::npos) return "";
  size_t at = q + 1;
  while (at <= target.size()) {
    size_t end = target.find('&', at);
    if (end == std::string::npos) end = target.size();
    const std::string pair = target.substr(at, end - at);
    const size_t eq = pair.find('=');
    if (pair.substr(0, eq) == key && eq != std::string::npos) {
      std::string value;
      const std::string raw = pair.substr(eq + 1);
      for (size_t i = 0; i < raw.size(); ++i) {
        if (raw[i] == '%' && i + 2 < raw.size() && std::isxdigit(static_cast<unsigned char>(raw[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(raw[i + 2]))) {
          value.push_back(static_cast<char>(std::stoi(raw.substr(i + 1, 2), nullptr, 16)));
          i += 2;
        } else {
          value.push_back(raw[i] == '+' ? ' ' : raw[i]);
        }
      }
      return value;
    }
    at = end + 1;
  }
  return "";
}

}  // namespace

class FoxgloveServer::Impl {
 public:
  explicit Impl(FoxgloveServerOptions options) : options_(std::move(options)) {}

  struct ClientChannel {
    std::string topic, encoding, schema_name;
  };
  // Per connection; touched only on the asio thread.
  struct Connection {
    uint64_t id = 0;
    Access access = Access::kCommand;
    std::map<uint32_t, uint32_t> subscription_of_channel;  // channel -> subscription id
    std::map<uint32_t, uint32_t> channel_of_subscription;
    std::map<uint32_t, ClientChannel> client_channels;
    std::set<uint32_t> owed;  // channels whose newest message waits for the socket to drain
  };
  struct Latest {
    uint64_t stamp_ns = 0;
    std::shared_ptr<const std::string> payload;
    uint64_t sequence = 0;
  };

  FoxgloveServerOptions options_;
  std::vector<ChannelSpec> channels_;
  std::function<void(const ClientMessage&)> on_client_message_;
  WsServer server_;
  std::thread thread_;
  std::unique_ptr<boost::asio::steady_timer> retry_timer_;
  std::atomic<bool> started_{false};
  int port_ = 0;
  std::string session_id_;

  std::map<websocketpp::connection_hdl, Connection, std::owner_less<websocketpp::connection_hdl>> connections_;
  std::map<uint64_t, websocketpp::connection_hdl> handles_;
  uint64_t next_connection_ = 1;
  std::atomic<size_t> connection_count_{0};

  mutable std::mutex latest_mutex_;
  std::vector<Latest> latest_;  // per channel, as are the two below
  std::deque<std::atomic<int>> subscribers_;
  std::deque<std::atomic<bool>> delivery_posted_;

  Access AccessOf(const std::string& target) const {
    if (!options_.access) return Access::kCommand;
    return options_.access(QueryValue(target, "token"));
  }

  void Start() {
    session_id_ = std::to_string(std::chrono::system_clock::now().time_since_epoch().count());

    server_.clear_access_channels(websocketpp::log::alevel::all);
    server_.clear_error_channels(websocketpp::log::elevel::all);
    server_.init_asio();
    server_.set_reuse_addr(true);
    server_.set_max_message_size(options_.max_client_message_bytes);
    server_.set_socket_init_handler([this](const websocketpp::connection_hdl&, boost::asio::ip::tcp::socket& socket) {
      boost::system::error_code ignored;
      socket.set_option(boost::asio::socket_base::send_buffer_size(options_.socket_send_buffer_bytes), ignored);
      socket.set_option(boost::asio::ip::tcp::no_delay(true), ignored);
    });
    server_.set_validate_handler([this](const websocketpp::connection_hdl& h) { return Validate(h); });
    server_.set_http_handler([this](const websocketpp::connection_hdl& h) { ServePage(h); });
    server_.set_open_handler([this](const websocketpp::connection_hdl& h) { Open(h); });
    server_.set_close_handler([this](const websocketpp::connection_hdl& h) { Close(h); });
    server_.set_fail_handler([this](const websocketpp::connection_hdl& h) { Close(h); });
    server_.set_message_handler([this](const websocketpp::connection_hdl& h, const WsServer::message_ptr& m) {
      Receive(h, m->get_opcode(), m->get_payload());
    });

    const std::string address = options_.host == "localhost" ? "127.0.0.1" : options_.host;
    const std::string where = options_.host + ":" + std::to_string(options_.port);
    boost::system::error_code asio_ec;
    const auto ip = boost::asio::ip::make_address(address, asio_ec);
    if (asio_ec) throw Error(ErrorCode::kInvalidArgument, "view: '" + options_.host + "' is not an IP address");
    websocketpp::lib::error_code ec;
    server_.listen(boost::asio::ip::tcp::endpoint(ip, static_cast<unsigned short>(options_.port)), ec);
    if (ec) throw Error(ErrorCode::kUnavailable, "view: cannot listen on " + where + ": " + ec.message());
    port_ = server_.get_local_endpoint(asio_ec).port();
    server_.start_accept(ec);
    if (ec) throw Error(ErrorCode::kUnavailable, "view: cannot accept on " + where + ": " + ec.message());
    retry_timer_ = std::make_unique<boost::asio::steady_timer>(server_.get_io_service());
    ScheduleRetry();
    started_ = true;
    thread_ = std::thread([this] {
      try {
        server_.run();
      } catch (const std::exception& e) {
        spdlog::error("view: server stopped: {}", e.what());
      }
    });
  }

  void Stop() {
    if (!started_) return;
    started_ = false;
    boost::asio::post(server_.get_io_service(), [this] {
      websocketpp::lib::error_code ec;
      server_.stop_listening(ec);
      retry_timer_->cancel();
      for (auto& [hdl, c] : connections_) {
        websocketpp::lib::error_code close_ec;
        server_.close(hdl, websocketpp::close::status::going_away, "server stopping", close_ec);
      }
    });
    // A client that never reads cannot complete the close handshake: the others get a moment,
    // then every socket still open is closed under it.
    for (int i = 0; i < 25 && connection_count_ > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    boost::asio::post(server_.get_io_service(), [this] {
      for (auto& [hdl, c] : connections_) {
        websocketpp::lib::error_code ec;
        WsServer::connection_ptr con = server_.get_con_from_hdl(hdl, ec);
        if (ec) continue;
        boost::system::error_code ignored;
        con->get_raw_socket().shutdown(boost::asio::ip::tcp::socket::shutdown_both, ignored);
        con->get_raw_socket().close(ignored);
      }
    });
    for (int i = 0; i < 25 && connection_count_ > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    server_.stop();
    if (thread_.joinable()) thread_.join();
  }

  bool Validate(const websocketpp::connection_hdl& h) {
    WsServer::connection_ptr con = server_.get_con_from_hdl(h);
    if (AccessOf(con->get_resource()) == Access::kNone) {
      con->set_status(websocketpp::http::status_code::unauthorized);
      return false;
    }
    for (const std::string& p : con->get_requested_subprotocols()) {
      if (p == kSubprotocol) {
        con->select_subprotocol(kSubprotocol);
        return true;
      }
    }
    con->set_status(websocketpp::http::status_code::bad_request);
    con->set_body(std::string("this server speaks the ") + kSubprotocol + " subprotocol only\n");
    return false;
  }

  void ServePage(const websocketpp::connection_hdl& h) {
    WsServer::connection_ptr con = server_.get_con_from_hdl(h);
    const std::string target = con->get_resource();
    const std::string path = target.substr(0, target.find('?'));
    if (con->get_request().get_method() != "GET" || (path != "/" && path != "/index.html") || options_.page.empty()) {
      con->set_status(websocketpp::http::status_code::not_found);
      con->set_body("not found\n");
      return;
    }
    if (AccessOf(target) == Access::kNone) {
      con->set_status(websocketpp::http::status_code::unauthorized);
      con->set_body("a token with the viewer role is needed: open /?token=...\n");
      return;
    }
    con->set_status(websocketpp::http::status_code::ok);
    con->append_header("Content-Type", "text/html; charset=utf-8");
    con->append_header("Cache-Control", "no-store");
    con->set_body(options_.page);
  }

  void Open(const websocketpp::connection_hdl& h) {
    WsServer::connection_ptr con = server_.get_con_from_hdl(h);
    Connection c;
    c.id = next_connection_++;
    c.access = AccessOf(con->get_resource());
    handles_[c.id] = h;
    connections_[h] = c;
    connection_count_ = connections_.size();

    Json info = {{"op", "serverInfo"},
                 {"name", options_.name},
                 {"capabilities", c.access == Access::kCommand ? Json::array({"clientPublish"}) : Json::array()},
                 {"supportedEncodings", Json::array({"json"})},
                 {"metadata", Json::object()},
                 {"sessionId", session_id_}};
    SendText(h, info.dump());
    Json advertise = {{"op", "advertise"}, {"channels", Json::array()}};
    for (size_t i = 0; i < channels_.size(); ++i) {
      const ChannelSpec& s = channels_[i];
      advertise["channels"].push_back({{"id", i},
                                       {"topic", s.topic},
                                       {"encoding", s.encoding},
                                       {"schemaName", s.schema_name},
                                       {"schema", s.schema},
                                       {"schemaEncoding", s.schema_encoding}});
    }
    SendText(h, advertise.dump());
  }

  void Close(const websocketpp::connection_hdl& h) {
    auto it = connections_.find(h);
    if (it == connections_.end()) return;
    for (const auto& [channel, sub] : it->second.subscription_of_channel) --subscribers_[channel];
    handles_.erase(it->second.id);
    connections_.erase(it);
    connection_count_ = connections_.size();
  }

  void SendText(const websocketpp::connection_hdl& h, const std::string& text) {
    websocketpp::lib::error_code ec;
    server_.send(h, text, websocketpp::frame::opcode::text, ec);
  }

  void SendStatusOn(const websocketpp::connection_hdl& h, int level, const std::string& message) {
    SendText(h, Json{{"op", "status"}, {"level", level}, {"message", message}}.dump());
  }

  void Receive(const websocketpp::connection_hdl& h, websocketpp::frame::opcode::value opcode,
               const std::string& payload) {
    auto it = connections_.find(h);
    if (it == connections_.end()) return;
    Connection& c = it->second;
    if (opcode == websocketpp::frame::opcode::binary) {
      ReceiveBinary(h, c, payload);
      return;
    }
    Json m;
    try {
      m = Json::parse(payload);
      const std::string op = m.at("op").get<std::string>();
      if (op == "subscribe") {
        for (const Json& s : m.at("subscriptions"))
          Subscribe(h, c, s.at("id").get<uint32_t>(), s.at("channelId").get<uint32_t>());
      } else if (op == "unsubscribe") {
        for (const Json& id : m.at("subscriptionIds")) Unsubscribe(c, id.get<uint32_t>());
      } else if (op == "advertise") {
        if (c.access != Access::kCommand) {
          SendStatusOn(h, 2, "advertise: publishing needs a token with the operator role");
          return;
        }
        for (const Json& ch : m.at("channels")) {
          ClientChannel cc{ch.at("topic").get<std::string>(), ch.at("encoding").get<std::string>(),
                           ch.value("schemaName", std::string())};
          if (cc.encoding != "json") {
            SendStatusOn(
                h, 2,
                "advertise: channel '" + cc.topic + "': encoding '" + cc.encoding + "' is not supported (json only)");
            continue;
          }
          c.client_channels[ch.at("id").get<uint32_t>()] = cc;
        }
      } else if (op == "unadvertise") {
        for (const Json& id : m.at("channelIds")) c.client_channels.erase(id.get<uint32_t>());
      } else {
        SendStatusOn(h, 1, "op '" + op + "' is not supported by this server");
      }
    } catch (const Json::exception& e) {
      SendStatusOn(h, 2, std::string("malformed message: ") + e.what());
    }
  }

  void ReceiveBinary(const websocketpp::connection_hdl& h, Connection& c, const std::string& payload) {
    if (payload.size() < 5 || static_cast<uint8_t>(payload[0]) != kClientMessageDataOpcode) {
      SendStatusOn(h, 2, "binary message: unknown opcode or too short");
      return;
    }
    const uint32_t channel = GetLe32(payload, 1);
    auto cc = c.client_channels.find(channel);
    if (cc == c.client_channels.end()) {
      SendStatusOn(h, 2, "client message on channel " + std::to_string(channel) + ", which was not advertised");
      return;
    }
    if (!on_client_message_) return;
    ClientMessage m{c.id, c.access, cc->second.topic, cc->second.schema_name, cc->second.encoding, payload.substr(5)};
    on_client_message_(m);
  }

  void Subscribe(const websocketpp::connection_hdl& h, Connection& c, uint32_t id, uint32_t channel) {
    if (channel >= channels_.size()) {
      SendStatusOn(h, 2, "subscribe: no channel " + std::to_string(channel));
      return;
    }
    if (c.channel_of_subscription.count(id) || c.subscription_of_channel.count(channel)) {
      SendStatusOn(h, 2,
                   "subscribe: subscription " + std::to_string(id) + " or channel " + std::to_string(channel) +
                       " is already in use");
      return;
    }
    c.channel_of_subscription[id] = channel;
    c.subscription_of_channel[channel] = id;
    ++subscribers_[channel];
    // A late subscriber gets the newest message at once (maps change rarely).
    SendNewest(h, c, channel);
  }

  void Unsubscribe(Connection& c, uint32_t id) {
    auto it = c.channel_of_subscription.find(id);
    if (it == c.channel_of_subscription.end()) return;
    c.subscription_of_channel.erase(it->second);
    c.owed.erase(it->second);
    --subscribers_[it->second];
    c.channel_of_subscription.erase(it);
  }

  // Sends the channel's newest message to one subscriber, or owes it while its socket is full.
  void SendNewest(const websocketpp::connection_hdl& h, Connection& c, uint32_t channel) {
    auto sub = c.subscription_of_channel.find(channel);
    if (sub == c.subscription_of_channel.end()) return;
    Latest latest;
    {
      std::lock_guard<std::mutex> lock(latest_mutex_);
      latest = latest_[channel];
    }
    if (!latest.payload) return;
    websocketpp::lib::error_code ec;
    WsServer::connection_ptr con = server_.get_con_from_hdl(h, ec);
    if (ec || con->get_state() != websocketpp::session::state::open) return;
    if (con->get_buffered_amount() >= options_.max_buffered_bytes) {
      c.owed.insert(channel);
      return;
    }
    c.owed.erase(channel);
    std::string frame;
    frame.reserve(13 + latest.payload->size());
    frame.push_back(static_cast<char>(kMessageDataOpcode));
    PutLe(frame, sub->second, 4);
    PutLe(frame, latest.stamp_ns, 8);
    frame.append(*latest.payload);
    con->send(frame, websocketpp::frame::opcode::binary);
  }

  void Deliver(uint32_t channel) {
    delivery_posted_[channel] = false;
    for (auto& [h, c] : connections_) SendNewest(h, c, channel);
  }

  void ScheduleRetry() {
    retry_timer_->expires_after(kRetryPeriod);
    retry_timer_->async_wait([this](const boost::system::error_code& ec) {
      if (ec) return;
      for (auto& [h, c] : connections_) {
        const std::set<uint32_t> owed = c.owed;
        for (uint32_t channel : owed) SendNewest(h, c, channel);
      }
      ScheduleRetry();
    });
  }

  void Publish(uint32_t channel, uint64_t stamp_ns, std::string payload) {
    if (channel >= channels_.size())
      throw Error(ErrorCode::kInvalidArgument, "view: no channel " + std::to_string(channel));
    {
      std::lock_guard<std::mutex> lock(latest_mutex_);
      Latest& l = latest_[channel];
      l.stamp_ns = stamp_ns;
      l.payload = std::make_shared<const std::string>(std::move(payload));
      ++l.sequence;
    }
    if (!started_ || subscribers_[channel] == 0) return;
    if (delivery_posted_[channel].exchange(true)) return;  // a delivery is queued; it takes the newest
    boost::asio::post(server_.get_io_service(), [this, channel] { Deliver(channel); });
  }
};

FoxgloveServer::FoxgloveServer(FoxgloveServerOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}

FoxgloveServer::~FoxgloveServer() { Stop(); }

uint32_t FoxgloveServer::Advertise(const ChannelSpec& channel) {
  if (impl_->started_) throw Error(ErrorCode::kFailedPrecondition, "view: channels are advertised before Start");
  impl_->channels_.push_back(channel);
  impl_->latest_.emplace_back();
  impl_->subscribers_.emplace_back(0);
  impl_->delivery_posted_.emplace_back(false);
  return static_cast<uint32_t>(impl_->channels_.size() - 1);
}

void FoxgloveServer::OnClientMessage(std::function<void(const ClientMessage&)> handler) {
  impl_->on_client_message_ = std::move(handler);
}

void FoxgloveServer::Start() { impl_->Start(); }
void FoxgloveServer::Stop() { impl_->Stop(); }
int FoxgloveServer::port() const { return impl_->port_; }

void FoxgloveServer::Publish(uint32_t channel, uint64_t stamp_ns, std::string payload) {
  impl_->Publish(channel, stamp_ns, std::move(payload));
}

bool FoxgloveServer::HasSubscribers(uint32_t channel) const {
  return channel < impl_->channels_.size() && impl_->subscribers_[channel] > 0;
}

void FoxgloveServer::SendStatus(uint64_t connection, int level, const std::string& message) {
  if (!impl_->started_) return;
  boost::asio::post(impl_->server_.get_io_service(), [this, connection, level, message] {
    auto it = impl_->handles_.find(connection);
    if (it != impl_->handles_.end()) impl_->SendStatusOn(it->second, level, message);
  });
}

size_t FoxgloveServer::connections() const { return impl_->connection_count_; }

}  // namespace navd::view
