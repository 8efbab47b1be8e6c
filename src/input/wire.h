// Raw device output as it crosses the wire, with its timestamp: what backends read, what
// simulated devices write, what --record stores and replay feeds back (decoded only in
// src/input, by input/decoder.h). Fixed size, so a
// frame can queue them without allocating.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>

#include "input/event.h"
#include "input/sink.h"

namespace mar {

enum class WireKind : uint8_t {
  UsbMidi = 1,    ///< USB-MIDI event packets (multiples of 4 bytes), a bulk IN transfer
  MidiBytes = 2,  ///< a MIDI 1.0 byte stream chunk (serial, ALSA raw)
  HidReport = 3,  ///< one HID input report (report-ID byte first when numbered)
  GpioEdge = 4,   ///< data[0] = line index in the device, data[1] = level after the edge
  // 5 was "an Event decoded by a backend" (recordings before MARREC02)
  EvdevEvent = 6, ///< one input_event: u16 type, u16 code, i32 value (little-endian host order)
  OscMessage = 7, ///< one OSC message (bundles are split into their messages)
  SdlControl = 8, ///< an SDL control that changed: u8 what (SdlWhat), u8 index, i32 value, lo, hi
  AudioPcm = 9,   ///< a block of mono 16-bit PCM (little-endian, up to 48 samples), oldest first
};

/// What an SdlControl record reports.
enum class SdlWhat : uint8_t { PadAxis = 0, PadButton = 1, MouseX = 2, MouseY = 3, MouseButton = 4, TouchX = 5, TouchY = 6, Touching = 7 };

const char* wire_kind_name(WireKind k);

struct WireRecord {
  static constexpr size_t kMax = 96;
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
    if (r.size) std::memcpy(r.data, b.data(), r.size);  // an empty span's data() may be null
    return r;
  }
};

/// One frame's wire records.
using WireSink = FixedSink<WireRecord>;

}  // namespace mar
