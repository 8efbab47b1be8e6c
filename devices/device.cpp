#include "devices/device.h"

#include <chrono>
#include <ctime>

namespace mar {

const char* device_state_name(DeviceState s) {
  switch (s) {
    case DeviceState::Waiting: return "waiting";
    case DeviceState::Connected: return "connected";
    case DeviceState::Unplugged: return "unplugged";
    case DeviceState::Denied: return "permission denied";
    case DeviceState::Unavailable: return "unavailable";
  }
  return "?";
}

int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return int64_t(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

void Backend::decode(WireDecoder& dec, const WireRecord& r, EventSink& out) {
  const uint64_t bad = dec.stats().malformed;
  size_t n = 0;
  dec.feed(r, [&](const Event& e) {
    out.push(e);
    ++n;
  });
  if (dec.stats().malformed != bad) count_malformed(dec.stats().malformed - bad);
  count_events(n);
}

std::string Backend::denied_hint(const std::string& path) {
  return "permission denied on " + path + ": install " + std::string(kUdevRule) +
         " and add yourself to the 'marionette' group (see README, Devices)";
}

DeviceSet::DeviceSet(int64_t epoch) : epoch_ns_(epoch) {}

DeviceSet::~DeviceSet() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  for (auto& p : ports_)
    if (p->phase.load() != Closed) p->b->close();
}

void DeviceSet::add(std::unique_ptr<Backend> b) {
  b->set_epoch(epoch_ns_);
  auto p = std::make_unique<Port>();
  p->b = std::move(b);
  ports_.push_back(std::move(p));
}

void DeviceSet::attempt(Port& p) {
  const DeviceState st = p.b->open();
  {
    std::lock_guard lock(p.problem_mutex);
    p.problem = st == DeviceState::Connected ? std::string() : p.b->problem();
  }
  if (st == DeviceState::Connected) {
    if (p.was_connected.load()) {
      const double ms = double(monotonic_ns() - p.lost_at.load()) * 1e-6;
      p.last_outage_ms = ms;
      if (ms > p.max_outage_ms.load()) p.max_outage_ms = ms;
      p.reconnects.fetch_add(1);
    }
    p.was_connected = true;
    p.gone = false;
    p.shown.store(uint8_t(DeviceState::Connected), std::memory_order_release);
    p.phase.store(Open, std::memory_order_release);  // hand the device to the frame thread
  } else if (!(st == DeviceState::Waiting && p.was_connected.load())) {
    p.shown.store(uint8_t(st), std::memory_order_release);  // an unplugged device stays "unplugged"
  }
}

void DeviceSet::start(int interval_ms) {
  interval_ms_ = interval_ms;
  for (auto& p : ports_) attempt(*p);
  thread_ = std::thread([this] { loop(); });
}

void DeviceSet::loop() {
  while (!stop_.load()) {
    for (auto& pp : ports_) {
      Port& p = *pp;
      switch (p.phase.load(std::memory_order_acquire)) {
        case Closed:
          attempt(p);
          break;
        case Open:
          if (!p.b->present()) p.gone.store(true, std::memory_order_release);
          break;
        case Lost:  // the frame thread has let go: close, then look for it again
          p.b->close();
          p.phase.store(Closed, std::memory_order_release);
          attempt(p);
          break;
      }
    }
    for (int slept = 0; slept < interval_ms_ && !stop_.load(); slept += 10)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

void DeviceSet::poll(int64_t now_ns, EventSink& out) {
  for (auto& pp : ports_) {
    Port& p = *pp;
    if (p.phase.load(std::memory_order_acquire) != Open) continue;
    if (p.gone.load(std::memory_order_acquire) || !p.b->poll(now_ns, out)) {
      p.lost_at.store(monotonic_ns());
      p.unplugs.fetch_add(1);
      p.shown.store(uint8_t(DeviceState::Unplugged), std::memory_order_release);
      p.phase.store(Lost, std::memory_order_release);
    }
  }
}

DeviceSet::Status DeviceSet::status(size_t i) const {
  const Port& p = *ports_[i];
  Status s;
  s.state = DeviceState(p.shown.load());
  s.unplugs = p.unplugs.load();
  s.reconnects = p.reconnects.load();
  s.malformed = p.b->malformed();
  s.events = p.b->events();
  s.last_outage_ms = p.last_outage_ms.load();
  s.max_outage_ms = p.max_outage_ms.load();
  return s;
}

std::string DeviceSet::problem(size_t i) const {
  std::lock_guard lock(ports_[i]->problem_mutex);
  return ports_[i]->problem;
}

}  // namespace mar
