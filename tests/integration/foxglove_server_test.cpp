// view::FoxgloveServer against clients on raw loopback sockets (minimal WebSocket framing written
// here, so the test sees exactly what goes over the wire): a viewer that never reads costs bounded
// memory and does not hold up the others, who get the newest message.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <string>
#include <thread>

#include "services/common/error.h"
#include "view/foxglove_server.h"

namespace navd::view {
namespace {

// A WebSocket client on a blocking socket: the opening handshake, masked text frames out, frames in.
class RawClient {
 public:
  RawClient(int port, int receive_buffer = 0) {
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    if (receive_buffer > 0) setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) throw std::runtime_error("connect");
    const std::string request =
        "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
        "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
        "Sec-WebSocket-Protocol: foxglove.websocket.v1\r\n\r\n";
    Write(request);
    std::string response;
    char c;
    while (response.find("\r\n\r\n") == std::string::npos && read(fd_, &c, 1) == 1) response.push_back(c);
    if (response.find(" 101 ") == std::string::npos) throw std::runtime_error("handshake: " + response);
  }
  ~RawClient() { close(fd_); }

  void SendText(const std::string& text) {
    std::string frame;
    frame.push_back(static_cast<char>(0x81));
    const uint8_t mask[4] = {1, 2, 3, 4};
    if (text.size() < 126) {
      frame.push_back(static_cast<char>(0x80 | text.size()));
    } else {
      frame.push_back(static_cast<char>(0x80 | 126));
      frame.push_back(static_cast<char>(text.size() >> 8));
      frame.push_back(static_cast<char>(text.size() & 0xff));
    }
    frame.append(reinterpret_cast<const char*>(mask), 4);
    for (size_t i = 0; i < text.size(); ++i) frame.push_back(static_cast<char>(text[i] ^ mask[i % 4]));
    Write(frame);
  }

  // The next frame's opcode and payload; false when the connection ends.
  bool Next(int& opcode, std::string& payload) {
    uint8_t h[2];
    if (!ReadExactly(h, 2)) return false;
    opcode = h[0] & 0x0f;
    uint64_t length = h[1] & 0x7f;
    if (length >= 126) {
      uint8_t ext[8];
      const int n = length == 126 ? 2 : 8;
      if (!ReadExactly(ext, n)) return false;
      length = 0;
      for (int i = 0; i < n; ++i) length = (length << 8) | ext[i];
    }
    payload.resize(length);
    return ReadExactly(reinterpret_cast<uint8_t*>(payload.data()), length);
  }

 private:
  void Write(const std::string& s) {
    if (write(fd_, s.data(), s.size()) != static_cast<ssize_t>(s.size())) throw std::runtime_error("write");
  }
  bool ReadExactly(uint8_t* out, size_t n) {
    size_t got = 0;
    while (got < n) {
      const ssize_t r = read(fd_, out + got, n - got);
      if (r <= 0) return false;
      got += static_cast<size_t>(r);
    }
    return true;
  }
  int fd_;
};

long ResidentKilobytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return 0;
}

TEST(FoxgloveServer, AViewerThatNeverReadsCostsBoundedMemoryAndOthersGetTheNewest) {
  FoxgloveServerOptions options;
  options.port = 0;
  FoxgloveServer server(options);
  const uint32_t channel = server.Advertise({"/big", "json", "test.Big", "{}"});
  server.Start();

  RawClient stalled(server.port(), 4096);  // subscribes, then never reads
  stalled.SendText(R"({"op":"subscribe","subscriptions":[{"id":7,"channelId":0}]})");
  RawClient reader(server.port());
  reader.SendText(R"({"op":"subscribe","subscriptions":[{"id":9,"channelId":0}]})");
  std::atomic<long> newest{-1};
  std::atomic<int> received{0};
  std::thread reading([&] {
    int opcode;
    std::string payload;
    while (reader.Next(opcode, payload)) {
      if (opcode != 2 || payload.size() < 13 || payload[0] != 1) continue;
      ++received;
      newest = std::stol(payload.substr(13, payload.find(' ', 13) - 13));
    }
  });
  for (int i = 0; i < 50 && server.connections() < 2; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_EQ(server.connections(), 2u);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // both subscriptions in

  const long before = ResidentKilobytes();
  const std::string filler(50 * 1024, 'x');
  const int messages = 2000;  // 100 MB in all
  for (int i = 0; i < messages; ++i) {
    server.Publish(channel, static_cast<uint64_t>(i), std::to_string(i) + " " + filler);
    // Paced, so that most messages are delivered one by one rather than taken over by a newer one.
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  for (int i = 0; i < 200 && newest != messages - 1; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const long grown = ResidentKilobytes() - before;
  EXPECT_EQ(newest, messages - 1) << "the reading viewer did not get the newest message";
  EXPECT_GT(received, 0);
  EXPECT_LT(grown, 30 * 1024) << "resident memory grew by " << grown << " kB for 100 MB published";
  std::printf("reader got %d of %d messages, the newest last; resident memory grew %ld kB\n", received.load(), messages,
              grown);
  server.Stop();
  reading.join();
}

TEST(FoxgloveServer, TheListenAddressIsCheckedAndATakenPortIsAnError) {
  FoxgloveServerOptions o;
  EXPECT_THROW(ParseListenAddress("--view", "localhost", o), Error);
  EXPECT_THROW(ParseListenAddress("--view", "1.2.3.4:99999", o), Error);
  EXPECT_THROW(ParseListenAddress("--view", ":80", o), Error);
  ParseListenAddress("--view", "127.0.0.1:0", o);
  FoxgloveServer first(o);
  first.Start();
  FoxgloveServerOptions same = o;
  same.port = first.port();
  FoxgloveServer second(same);
  try {
    second.Start();
    ADD_FAILURE() << "a second server bound a taken port";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot listen on 127.0.0.1:" + std::to_string(first.port())),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace navd::view
