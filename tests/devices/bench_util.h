// Helpers for the virtual-bench tests: poll a DeviceSet until a condition holds, or run
// its frames in virtual time.
#pragma once

#include "devices/device.h"

#include <chrono>
#include <functional>
#include <thread>
#include <vector>

namespace mar::test {

/// One frame at `now`: polls, decodes with each connection's decoder, settles, and appends
/// the events to `out`.
inline void poll_frame(DeviceSet& set, int64_t now, Event (&buf)[1024], std::vector<WireRecord>& wires,
                       std::vector<Event>& out) {
  EventSink sink{buf, std::size(buf)};
  WireSink ws{wires.data(), wires.size()};
  set.poll(now, ws);
  for (size_t k = 0; k < ws.n; ++k) set.decode(wires[k], sink);
  set.settle(now, sink);
  out.insert(out.end(), buf, buf + sink.n);
}

/// Polls `set` like frames do (every `period_ms`) for at most `timeout_ms`, decoding the
/// wire records with each connection's decoder and appending the events to `out`, until
/// `done()` holds. Returns whether it did.
inline bool poll_until(DeviceSet& set, int64_t epoch, std::vector<Event>& out, const std::function<bool()>& done,
                       int timeout_ms = 5000, int period_ms = 2) {
  Event buf[1024];
  std::vector<WireRecord> wires(1024);
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (std::chrono::steady_clock::now() < end) {
    poll_frame(set, monotonic_ns() - epoch, buf, wires, out);
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(period_ms));
  }
  return done();
}

/// Runs frames in virtual time: at each frame time `now` (show time, `from_ns` to `to_ns`
/// every `period_ns`) `feed(now)` first writes what the emulated device has produced by
/// then, and the frame then polls, decodes and settles at `now`, appending the events to
/// `out`. One thread, so what each frame reads never depends on how busy the machine is.
inline void poll_frames(DeviceSet& set, int64_t from_ns, int64_t to_ns, int64_t period_ns,
                        const std::function<void(int64_t)>& feed, std::vector<Event>& out) {
  Event buf[1024];
  std::vector<WireRecord> wires(1024);
  for (int64_t now = from_ns; now <= to_ns; now += period_ns) {
    feed(now);
    poll_frame(set, now, buf, wires, out);
  }
}

}  // namespace mar::test
