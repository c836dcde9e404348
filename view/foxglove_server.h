#pragma once
// A Foxglove WebSocket server (subprotocol foxglove.websocket.v1, the open protocol Foxglove
// Studio speaks) on one TCP listener, which also serves one HTML page over plain HTTP GET /.
// Channels are advertised before Start; Publish keeps each channel's newest message and hands it
// to every subscriber. A client that reads slowly gets the newest message when its socket has
// drained, never a backlog, and Publish never waits on a client. Clients may publish on channels
// of their own (capability clientPublish, JSON encoding); those messages reach the handler.
//
// Access: with an `access` function, each connection (and each page request) is judged by the
// `token` query parameter of its URL (ws://host:port/?token=...): none is refused with HTTP 401,
// watch may subscribe, command may also publish. Without one, everyone may command.
//
// websocketpp (Debian's libwebsocketpp-dev) does the WebSocket and HTTP framing on one asio
// thread; its headers stay inside foxglove_server.cpp.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace navd::view {

enum class Access { kNone = 0, kWatch = 1, kCommand = 2 };

struct ChannelSpec {
  std::string topic;              // "/map"
  std::string encoding = "json";  // message encoding
  std::string schema_name;        // "foxglove.Grid"
  std::string schema;             // the schema text (a JSON Schema for json channels)
  std::string schema_encoding = "jsonschema";
};

// A message a client published on one of its channels.
struct ClientMessage {
  uint64_t connection = 0;  // which client (for SendStatus)
  Access access = Access::kCommand;
  std::string topic, schema_name, encoding;
  std::string payload;
};

struct FoxgloveServerOptions {
  std::string host = "127.0.0.1";  // an IP address or "localhost"
  int port = 8765;                 // 0: any free port (see port())
  std::string name = "navd";       // serverInfo's name
  std::string page;                // HTML served at GET /; empty: 404
  // A subscriber is sent a channel's message only while fewer bytes than this wait in its socket's
  // send buffer; otherwise the newest message waits for it (one per channel).
  size_t max_buffered_bytes = 256 * 1024;
  // Each connection's kernel send buffer (SO_SNDBUF): bounds what a stalled client holds below
  // the queue above (Linux grows it to megabytes by itself).
  int socket_send_buffer_bytes = 128 * 1024;
  size_t max_client_message_bytes = 64 * 1024;
  std::function<Access(std::string_view token)> access;  // empty: every client may command
};

// "HOST:PORT" of a --view option into options.host and options.port. Throws navd::Error
// (kInvalidArgument) naming `option` when it is not HOST:PORT with a port in 0..65535.
void ParseListenAddress(const std::string& option, const std::string& text, FoxgloveServerOptions& options);

class FoxgloveServer {
 public:
  explicit FoxgloveServer(FoxgloveServerOptions options);
  ~FoxgloveServer();
  FoxgloveServer(const FoxgloveServer&) = delete;
  FoxgloveServer& operator=(const FoxgloveServer&) = delete;

  // Before Start. Returns the channel's id.
  uint32_t Advertise(const ChannelSpec& channel);
  // Called on the server's thread for each message a client publishes on one of its channels;
  // it should return quickly (hand long work to another thread). Before Start.
  void OnClientMessage(std::function<void(const ClientMessage&)> handler);

  // Binds and starts serving. Throws navd::Error(kUnavailable) naming the address when it cannot
  // listen (in use, not an address of this host).
  void Start();
  void Stop();
  // The bound port (after Start).
  int port() const;

  // The channel's newest message (stamp in nanoseconds); thread-safe, never blocks on clients.
  void Publish(uint32_t channel, uint64_t stamp_ns, std::string payload);
  // Whether any client is subscribed to the channel (to skip encoding what nobody reads).
  bool HasSubscribers(uint32_t channel) const;
  // A status message to one client (level 0 info, 1 warning, 2 error); thread-safe.
  void SendStatus(uint64_t connection, int level, const std::string& message);
  size_t connections() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace navd::view
