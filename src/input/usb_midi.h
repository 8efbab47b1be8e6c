// USB-MIDI 1.0 event packets (USB Device Class Definition for MIDI Devices 1.0, §4):
// 4 bytes = (cable << 4 | CIN), then up to three MIDI bytes; CIN gives the length.
// CIN 0xF carries a single byte (realtime, or one SysEx data byte); CIN 0x5 is both
// "SysEx ends with F7" and "1-byte system common" (F6). Each cable's payload bytes run
// through its own MIDI 1.0 stream decoder, so SysEx assembly and policy live in one place.
#pragma once

#include "input/midi.h"

#include <array>
#include <cstdint>
#include <memory>
#include <span>

namespace mar {

struct UsbMidiPacket {
  uint8_t cable = 0, cin = 0;
  uint8_t payload[3] = {0, 0, 0};
  uint8_t size = 0;
  bool is_sysex = false, sysex_start = false, sysex_end = false;
};

/// Payload length of a Code Index Number (reserved CINs 0 and 1 carry three bytes).
int usb_midi_cin_length(uint8_t cin);
UsbMidiPacket usb_midi_decode(const uint8_t packet[4]);

enum class UsbMidiEncodeError { None, EmptyPayload, InvalidPayloadSize, InvalidPayloadStatus };
const char* usb_midi_error_name(UsbMidiEncodeError e);
/// Packs one message (or a SysEx piece of 1-3 bytes) into a packet. Extra bytes beyond
/// the message's length are ignored; a SysEx piece without F7 must be 3 bytes (CIN 4) or a
/// single data byte (CIN 0xF).
UsbMidiEncodeError usb_midi_encode(uint8_t cable, std::span<const uint8_t> payload, uint8_t packet[4]);

/// Decodes a stream of packets (a bulk IN transfer) into MIDI messages per cable.
/// Trailing bytes that do not make a whole packet are dropped and counted.
class UsbMidiDecoder {
 public:
  explicit UsbMidiDecoder(size_t sysex_cap = 1024);
  /// `on(uint8_t cable, const MidiMessage&)` per message.
  template <class F>
  void feed(std::span<const uint8_t> bytes, F&& on) {
    size_t i = 0;
    for (; i + 4 <= bytes.size(); i += 4) {
      const UsbMidiPacket p = usb_midi_decode(bytes.data() + i);
      if (p.cin == 0 && p.payload[0] == 0 && p.payload[1] == 0 && p.payload[2] == 0) continue;  // padding
      MidiStreamDecoder& d = cable(p.cable);
      for (int k = 0; k < p.size; ++k) d.feed_byte(p.payload[k], [&](const MidiMessage& m) { on(p.cable, m); });
    }
    dropped_bytes_ += bytes.size() - i;
  }
  /// One stream decoder per cable, all made at construction (no allocation while feeding).
  MidiStreamDecoder& cable(uint8_t c);
  uint64_t dropped_bytes() const { return dropped_bytes_; }
  void reset();

 private:
  size_t sysex_cap_;
  std::array<std::unique_ptr<MidiStreamDecoder>, 16> cables_{};
  uint64_t dropped_bytes_ = 0;
};

}  // namespace mar
