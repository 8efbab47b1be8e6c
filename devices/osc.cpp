// OSC over UDP: a receiver thread reads datagrams, splits bundles into their messages and
// hands each message's bytes to the frame through a ring (the wire records); the OSC
// decoder (input/osc.cpp) parses them and matches the show's bound address patterns. The
// socket is bound to 127.0.0.1 unless the show names another host.
#include "devices/backends.h"
#include "devices/spsc.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace mar {
namespace {

class OscBackend final : public Backend {
 public:
  using Backend::Backend;
  ~OscBackend() override { close(); }
  DeviceState open() override;
  void close() override {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  bool poll(int64_t now_ns, WireSink& out) override {
    WireRecord r;
    while (ring_.pop(r)) {
      r.t_ns = now_ns;  // UDP has no device time: a message is stamped when the frame takes it
      emit(r, out);
    }
    return true;
  }

 private:
  void receive();
  void packet(const uint8_t* data, size_t size, int depth);
  int fd_ = -1;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  SpscRing<WireRecord, 1024> ring_;
};

DeviceState OscBackend::open() {
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(uint16_t(spec_.port));
  if (fd_ < 0 || inet_pton(AF_INET, spec_.host.c_str(), &a.sin_addr) != 1 ||
      bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    problem_ = "OSC: cannot listen on " + spec_.host + ":" + std::to_string(spec_.port) + " (" + std::strerror(errno) + ")";
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    return errno == EACCES ? DeviceState::Denied : DeviceState::Unavailable;
  }
  identity_ = "osc.udp://" + spec_.host + ":" + std::to_string(spec_.port);
  node_ = identity_;
  config_ = DecoderConfig{};
  config_.kind = WireKind::OscMessage;
  config_.osc_patterns = spec_.osc_addresses;
  stop_ = false;
  thread_ = std::thread([this] { receive(); });
  problem_.clear();
  return DeviceState::Connected;
}

void OscBackend::receive() {
  uint8_t buf[65536];
  while (!stop_) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, 50) <= 0) continue;
    const ssize_t n = recv(fd_, buf, sizeof buf, 0);
    if (n > 0) packet(buf, size_t(n), 0);
  }
}

void OscBackend::packet(const uint8_t* data, size_t size, int depth) {
  if (size >= 16 && std::memcmp(data, "#bundle", 8) == 0) {
    if (depth >= 8) {
      count_malformed();  // bundles nested deeper than any sender needs
      return;
    }
    for (size_t off = 16; off + 4 <= size;) {
      uint32_t len = 0;
      std::memcpy(&len, data + off, 4);
      len = ntohl(len);
      if (len > size - off - 4) {
        count_malformed();
        return;
      }
      packet(data + off + 4, len, depth + 1);
      off += 4 + len;
    }
    return;
  }
  // A message too long for a wire record, or one the frame has no room for, is dropped
  // and counted; the decoder judges the rest.
  if (size > WireRecord::kMax || !ring_.push(WireRecord::make(0, WireKind::OscMessage, {data, size}, source_)))
    count_malformed();
}

}  // namespace

std::unique_ptr<Backend> make_osc_backend(const DeviceSpec& s, uint16_t source) {
  return std::make_unique<OscBackend>(s, source);
}

}  // namespace mar
