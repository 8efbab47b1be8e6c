// Helpers for the virtual-bench tests: poll a DeviceSet until a condition holds.
#pragma once

#include "devices/device.h"

#include <chrono>
#include <functional>
#include <thread>
#include <vector>

namespace mar::test {

/// Polls `set` like frames do (every `period_ms`) for at most `timeout_ms`, decoding the
/// wire records with each connection's decoder and appending the events to `out`, until
/// `done()` holds. Returns whether it did.
inline bool poll_until(DeviceSet& set, int64_t epoch, std::vector<Event>& out, const std::function<bool()>& done,
                       int timeout_ms = 5000, int period_ms = 2) {
  Event buf[1024];
  std::vector<WireRecord> wires(1024);
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (std::chrono::steady_clock::now() < end) {
    EventSink sink{buf, std::size(buf)};
    WireSink ws{wires.data(), wires.size()};
    const int64_t now = monotonic_ns() - epoch;
    set.poll(now, ws);
    for (size_t k = 0; k < ws.n; ++k) set.decode(wires[k], sink);
    set.settle(now, sink);
    out.insert(out.end(), buf, buf + sink.n);
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(period_ms));
  }
  return done();
}

}  // namespace mar::test
