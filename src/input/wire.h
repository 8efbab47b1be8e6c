// Raw device output as it crosses the wire, with its timestamp: what backends read, what
// simulated devices write, what --record stores and replay feeds back. Fixed size, so a
// frame can queue them without allocating.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>

#include "input/event.h"

namespace mar {

enum class WireKind : uint8_t {
  UsbMidi = 1,    ///< USB-MIDI event packets (multiples of 4 bytes), a bulk IN transfer
  MidiBytes = 2,  ///< a MIDI 1.0 byte stream chunk (serial, ALSA raw)
  HidReport = 3,  ///< one HID input report (report-ID byte first when numbered)
  GpioEdge = 4,   ///< data[0] = line index in the device, data[1] = level after the edge
  Event = 5,      ///< an Event decoded by a hardware backend (data = the Event's bytes)
};

struct WireRecord {
  static constexpr size_t kMax = 64;
  int64_t t_ns = 0;
  uint16_t source = 0;
  WireKind kind = WireKind::UsbMidi;
  uint8_t size = 0;
  uint8_t data[kMax] = {};
  std::span<const uint8_t> bytes() const { return {data, size}; }
  static WireRecord make(int64_t t, WireKind k, std::span<const uint8_t> b, uint16_t source = 0) {
    WireRecord r;
    r.t_ns = t;
    r.kind = k;
    r.source = source;
    r.size = uint8_t(b.size() < kMax ? b.size() : kMax);
    std::memcpy(r.data, b.data(), r.size);
    return r;
  }
  /// Wraps an Event decoded by a backend, so recording and replay see it like wire data.
  static WireRecord of(const Event& e) {
    static_assert(std::is_trivially_copyable_v<Event> && sizeof(Event) <= kMax);
    WireRecord r;
    r.t_ns = e.t_ns;
    r.kind = WireKind::Event;
    r.source = e.source;
    r.size = sizeof(Event);
    std::memcpy(r.data, &e, sizeof(Event));
    return r;
  }
};

}  // namespace mar
