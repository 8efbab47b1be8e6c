// OSC over UDP with liblo: messages (and bundles) whose address matches a bound pattern
// become HidValue events on the vendor page (number 0xFF000000 | binding index). The
// socket is bound to 127.0.0.1 unless the show names another host. liblo allocates while
// parsing, so a receiver thread parses and hands events to the frame through a ring.
#include "devices/backends.h"
#include "devices/spsc.h"

#include <arpa/inet.h>
#include <lo/lo.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>

namespace mar {
namespace {

// The Event for a message at `path` whose arguments are `types`/`argv`; returns the index of
// the first pattern in `patterns` that matches, or -1 (no event).
int osc_event(const std::vector<std::string>& patterns, const char* path, const char* types, lo_arg** argv, Event& e) {
  int hit = -1;
  for (size_t i = 0; i < patterns.size() && hit < 0; ++i)
    if (lo_pattern_match(path, patterns[i].c_str()) || lo_pattern_match(patterns[i].c_str(), path)) hit = int(i);
  if (hit < 0) return -1;
  e.kind = ControlKind::HidValue;
  e.number = 0xFF000000u | uint32_t(hit);
  e.lo = 0;
  e.hi = 1;
  e.value = 1;
  switch (types && *types ? types[0] : 0) {
    case 'f': e.value = int32_t(std::lround(double(argv[0]->f) * 65535)); e.hi = 65535; break;
    case 'd': e.value = int32_t(std::lround(argv[0]->d * 65535)); e.hi = 65535; break;
    case 'i': e.value = argv[0]->i; e.hi = 127; break;
    case 'h': e.value = int32_t(argv[0]->h); e.hi = 127; break;
    case 'T': e.value = 1; break;
    case 'F': e.value = 0; break;
    default: break;  // no argument: a trigger
  }
  return hit;
}

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
  bool poll(int64_t now_ns, EventSink& out) override {
    Event e;
    size_t n = 0;
    while (ring_.pop(e)) {
      e.t_ns = now_ns;
      e.source = source_;
      out.push(e);
      ++n;
    }
    count_events(n);
    return true;
  }

 private:
  void receive();
  void packet(uint8_t* data, size_t size, int depth);
  int fd_ = -1;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  SpscRing<Event, 1024> ring_;
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

void OscBackend::packet(uint8_t* data, size_t size, int depth) {
  if (size >= 16 && std::memcmp(data, "#bundle", 8) == 0 && depth < 8) {
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
  int result = 0;
  lo_message m = lo_message_deserialise(data, size, &result);
  if (!m) {
    count_malformed();  // not OSC: dropped
    return;
  }
  const char* path = reinterpret_cast<const char*>(data);  // validated by the parser
  Event e;
  if (osc_event(spec_.osc_addresses, path, lo_message_get_types(m), lo_message_get_argv(m), e) >= 0 && !ring_.push(e))
    count_malformed();
  lo_message_free(m);
}

}  // namespace

std::unique_ptr<Backend> make_osc_backend(const DeviceSpec& s, uint16_t source) {
  return std::make_unique<OscBackend>(s, source);
}

}  // namespace mar
