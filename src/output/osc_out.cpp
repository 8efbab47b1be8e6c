#include "output/osc_out.h"

#include <lo/lo.h>
#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <chrono>
#include <cmath>
#include <cstdio>

namespace mar {

namespace {

const char* state_name(uint8_t s) {
  static const char* names[] = {"waiting", "connected", "unplugged", "denied", "unavailable"};  // DeviceState's order
  return s < 5 ? names[s] : "unknown";
}

constexpr size_t kMaxBundle = 1200;  // under a typical path MTU

}  // namespace

struct OscOut::Link {
  int fd = -1;  ///< a UDP socket connected to the receiver (so a refusal or no route is reported)
  std::vector<std::string> handle, key, swap, trigger, device;
  std::string frame;
  ShowState sent;  ///< what a reader has (NaN or out of range where nothing was sent yet)
  bool said = false;
  std::vector<uint8_t> buf = std::vector<uint8_t>(2048);
  ~Link() {
    if (fd >= 0) ::close(fd);
  }
};

std::unique_ptr<OscOut> OscOut::open(const OscOutOptions& o, const ShowStateLayout& layout, std::string* error) {
  const std::string where = o.host + ":" + std::to_string(o.port);
  if (o.port < 1 || o.port > 65535) {
    *error = "[osc_out] port " + std::to_string(o.port) + ": 1..65535";
    return nullptr;
  }
  addrinfo hints{};
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  if (const int e = getaddrinfo(o.host.c_str(), std::to_string(o.port).c_str(), &hints, &found); e != 0) {
    *error = "[osc_out] " + where + ": " + gai_strerror(e);
    return nullptr;
  }
  int fd = -1;
  int last = 0;
  for (addrinfo* a = found; a && fd < 0; a = a->ai_next) {
    fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (fd >= 0 && ::connect(fd, a->ai_addr, a->ai_addrlen) != 0) {
      last = errno;
      ::close(fd);
      fd = -1;
    }
  }
  freeaddrinfo(found);
  if (fd < 0) {
    *error = "[osc_out] " + where + ": " + std::strerror(last ? last : errno);
    return nullptr;
  }
  std::unique_ptr<OscOut> out(new OscOut());
  out->o_ = o;
  out->o_.rate = std::clamp(o.rate, 1.0, 1000.0);
  out->layout_ = layout;
  for (ShowState& s : out->slots_) s.size_for(layout);
  auto link = std::make_unique<Link>();
  link->fd = fd;
  // (a cast's: the character's name after the prefix)
  auto address = [&](const std::vector<std::string>& who, size_t i, const char* kind, const std::string& n) {
    return o.prefix + (i < who.size() && !who[i].empty() ? "/" + who[i] : std::string()) + kind + n;
  };
  for (size_t i = 0; i < layout.handles.size(); ++i) link->handle.push_back(address(layout.handle_who, i, "/handle/", layout.handles[i]));
  for (size_t i = 0; i < layout.keys.size(); ++i) link->key.push_back(address(layout.key_who, i, "/key/", layout.keys[i]));
  for (size_t i = 0; i < layout.swaps.size(); ++i) link->swap.push_back(address(layout.swap_who, i, "/swap/", layout.swaps[i]));
  for (size_t i = 0; i < layout.triggers.size(); ++i)
    link->trigger.push_back(address(layout.trigger_who, i, "/trigger/", layout.triggers[i]));
  for (const auto& n : layout.devices) link->device.push_back(o.prefix + "/device/" + n);
  link->frame = o.prefix + "/frame";
  link->sent.size_for(layout);
  for (Vec2& h : link->sent.handles) h = Vec2(NAN, NAN);
  for (double& k : link->sent.keys) k = NAN;
  for (int& s : link->sent.swaps) s = -1;
  for (uint8_t& t : link->sent.triggers) t = 255;
  for (uint8_t& d : link->sent.devices) d = 255;
  link->sent.frame_ms = NAN;
  out->link_ = std::move(link);
  out->thread_ = std::thread([p = out.get()] { p->run(); });
  return out;
}

void OscOut::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

OscOut::~OscOut() { stop(); }

void OscOut::publish() { back_ = mid_.exchange(back_ | 4) & 3; }

void OscOut::run() {
  Link& l = *link_;
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(1.0 / o_.rate));
  auto next = std::chrono::steady_clock::now();
  lo_bundle b = nullptr;
  auto send = [&] {
    if (!b) return;
    size_t n = l.buf.size();
    const bool packed = lo_bundle_serialise(b, l.buf.data(), &n) != nullptr;
    if (!packed || ::send(l.fd, l.buf.data(), n, MSG_DONTWAIT | MSG_NOSIGNAL) < 0) {
      const int e = errno;
      errors_.fetch_add(1);
      if (!l.said) {
        l.said = true;
        std::fprintf(stderr, "warning: OSC out to %s:%d: %s (counted; the show goes on)\n", o_.host.c_str(), o_.port,
                     packed ? std::strerror(e) : "a bundle too large to send");
      }
    } else {
      bundles_.fetch_add(1);
    }
    lo_bundle_free_recursive(b);
    b = nullptr;
  };
  auto add = [&](const std::string& path, lo_message m) {
    if (b && lo_bundle_length(b) + lo_message_length(m, path.c_str()) + 16 > kMaxBundle) send();
    if (!b) b = lo_bundle_new(lo_timetag{0, 1});  // "immediately" (LO_TT_IMMEDIATE, without its C compound literal)
    lo_bundle_add_message(b, path.c_str(), m);
    messages_.fetch_add(1);
  };
  while (true) {
    const bool last = stop_.load();
    if (mid_.load() & 4) {
      front_ = mid_.exchange(front_) & 3;
      const ShowState& s = slots_[front_];
      ShowState& was = l.sent;
      for (size_t i = 0; i < s.handles.size(); ++i)
        if (!((s.handles[i] - was.handles[i]).cwiseAbs().maxCoeff() <= 0.01)) {  // (NaN: never sent)
          lo_message m = lo_message_new();
          lo_message_add_float(m, float(s.handles[i].x()));
          lo_message_add_float(m, float(s.handles[i].y()));
          add(l.handle[i], m);
          was.handles[i] = s.handles[i];
        }
      for (size_t i = 0; i < s.keys.size(); ++i)
        if (!(std::abs(s.keys[i] - was.keys[i]) <= 1e-4)) {
          lo_message m = lo_message_new();
          lo_message_add_float(m, float(s.keys[i]));
          add(l.key[i], m);
          was.keys[i] = s.keys[i];
        }
      for (size_t i = 0; i < s.swaps.size(); ++i)
        if (s.swaps[i] != was.swaps[i] && s.swaps[i] >= 0 && size_t(s.swaps[i]) < layout_.swap_members[i].size()) {
          lo_message m = lo_message_new();
          lo_message_add_string(m, layout_.swap_members[i][size_t(s.swaps[i])].c_str());
          add(l.swap[i], m);
          was.swaps[i] = s.swaps[i];
        }
      for (size_t i = 0; i < s.triggers.size(); ++i)
        if (s.triggers[i] != was.triggers[i]) {
          lo_message m = lo_message_new();
          lo_message_add_int32(m, s.triggers[i]);
          add(l.trigger[i], m);
          was.triggers[i] = s.triggers[i];
        }
      for (size_t i = 0; i < s.devices.size(); ++i)
        if (s.devices[i] != was.devices[i]) {
          lo_message m = lo_message_new();
          lo_message_add_string(m, state_name(s.devices[i]));
          add(l.device[i], m);
          was.devices[i] = s.devices[i];
        }
      if (!(std::abs(s.frame_ms - was.frame_ms) <= 0.01 && std::abs(s.latency_ms - was.latency_ms) <= 0.01)) {
        lo_message m = lo_message_new();
        lo_message_add_float(m, float(s.frame_ms));
        lo_message_add_float(m, float(s.latency_ms));
        add(l.frame, m);
        was.frame_ms = s.frame_ms;
        was.latency_ms = s.latency_ms;
      }
      send();
    }
    if (last) break;
    next += period;
    const auto now = std::chrono::steady_clock::now();
    if (next < now) next = now;  // (behind: no burst to catch up)
    std::this_thread::sleep_until(next);
  }
}

}  // namespace mar
