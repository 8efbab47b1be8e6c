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

namespace {
std::atomic<ReadClock*> g_read_clock{nullptr};
}  // namespace

void set_read_clock(ReadClock* c) { g_read_clock.store(c, std::memory_order_release); }

int64_t Backend::read_time() const {
  const int64_t now = monotonic_ns() - epoch_ns_;
  ReadClock* c = g_read_clock.load(std::memory_order_acquire);
  return c ? c->stamp(node_, now) : now;
}

void Backend::read_taken() const {
  if (ReadClock* c = g_read_clock.load(std::memory_order_acquire)) c->taken(node_);
}

std::string Backend::denied_hint(const std::string& path) {
  return "permission denied on " + path + ": install " + std::string(kUdevRule) +
         " and add yourself to the 'marionette' group (see docs/devices.md, udev rule)";
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
  if (port_of_source_.size() <= b->source()) port_of_source_.resize(size_t(b->source()) + 1, -1);
  port_of_source_[b->source()] = int(ports_.size());
  auto p = std::make_unique<Port>();
  p->b = std::move(b);
  ports_.push_back(std::move(p));
}

void DeviceSet::attempt(Port& p) {
  DeviceState st = p.b->open();
  std::string bad_config;
  if (st == DeviceState::Connected) {
    // A fresh decoder for this connection, in the slot the frame thread is not reading.
    const uint8_t k = p.generation.load() == 0 ? 0 : uint8_t(1 - p.slot);
    std::string err;
    auto dec = make_decoder(p.b->decoder_config(), p.b->source(), &err);
    if (!dec) {
      p.b->close();
      st = DeviceState::Unavailable;
      bad_config = p.b->identity() + ": " + err;
    } else {
      p.slots[k].dec = std::move(dec);
      p.slots[k].info = p.b->decoder_config().serialize();
      p.slot = k;
      p.live.store(k, std::memory_order_relaxed);
      p.generation.fetch_add(1, std::memory_order_relaxed);
    }
  }
  {
    std::lock_guard lock(p.problem_mutex);
    p.problem = st == DeviceState::Connected ? std::string() : !bad_config.empty() ? bad_config : p.b->problem();
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

void DeviceSet::poll(int64_t now_ns, WireSink& out) {
  for (auto& pp : ports_) {
    Port& p = *pp;
    if (p.phase.load(std::memory_order_acquire) != Open) continue;
    const uint8_t live = p.live.load(std::memory_order_relaxed);  // ordered by the phase's acquire
    if (p.polled_once && live != p.polled) {
      // A new connection: the previous decoder's counts are kept, and the reconnect thread
      // may rebuild that slot only after this thread has let go of the device again.
      const Decoder& old = *p.slots[p.polled].dec;
      p.retired_malformed.fetch_add(old.stats().malformed, std::memory_order_relaxed);
      p.retired_events.fetch_add(old.stats().events, std::memory_order_relaxed);
    }
    p.polled = live;
    p.polled_once = true;
    if (p.gone.load(std::memory_order_acquire) || !p.b->poll(now_ns, out)) {
      p.lost_at.store(monotonic_ns());
      p.unplugs.fetch_add(1);
      p.shown.store(uint8_t(DeviceState::Unplugged), std::memory_order_release);
      p.phase.store(Lost, std::memory_order_release);
    }
  }
}

void DeviceSet::decode(const WireRecord& r, EventSink& out) {
  const int k = r.source < port_of_source_.size() ? port_of_source_[r.source] : -1;
  Port* p = k >= 0 ? ports_[size_t(k)].get() : nullptr;
  if (!p || !p->polled_once) {
    ++out.dropped;
    return;
  }
  p->slots[p->polled].dec->feed(r, out);
}

void DeviceSet::settle(int64_t now_ns, EventSink& out) {
  for (auto& pp : ports_)
    if (pp->polled_once && pp->phase.load(std::memory_order_acquire) == Open) pp->slots[pp->polled].dec->settle(now_ns, out);
}

bool DeviceSet::take_connected(size_t i) {
  Port& p = *ports_[i];
  if (!p.polled_once) return false;
  const uint64_t g = p.generation.load(std::memory_order_relaxed);
  if (g == p.seen_generation) return false;
  p.seen_generation = g;
  return true;
}

std::span<const uint8_t> DeviceSet::description(size_t i) const {
  const Port& p = *ports_[i];
  return p.slots[p.polled].info;
}

std::span<const uint8_t> DeviceSet::last_sysex(size_t i, uint64_t& count) const {
  count = 0;
  if (i >= ports_.size() || !ports_[i]->polled_once) return {};
  const Port& p = *ports_[i];
  return p.slots[p.polled].dec->last_sysex(count);
}

DeviceSet::Status DeviceSet::status(size_t i) const {
  const Port& p = *ports_[i];
  Status s;
  s.state = DeviceState(p.shown.load());
  s.unplugs = p.unplugs.load();
  s.reconnects = p.reconnects.load();
  s.records = p.b->records();
  s.malformed = p.b->malformed();
  s.malformed += p.retired_malformed.load(std::memory_order_relaxed);
  s.events = p.retired_events.load(std::memory_order_relaxed);
  if (p.polled_once) {  // the frame's decoder (the frame thread's own)
    s.malformed += p.slots[p.polled].dec->stats().malformed;
    s.events += p.slots[p.polled].dec->stats().events;
  }
  s.last_outage_ms = p.last_outage_ms.load();
  s.max_outage_ms = p.max_outage_ms.load();
  return s;
}

std::string DeviceSet::problem(size_t i) const {
  std::lock_guard lock(ports_[i]->problem_mutex);
  return ports_[i]->problem;
}

}  // namespace mar
