// MIDI 1.0 byte-stream decoder (DIN/UART, serial, ALSA raw, the payload of USB-MIDI packets).
//
// Follows the MIDI 1.0 specification:
// - running status for channel messages; it survives realtime bytes and is cleared by any
//   system common or system exclusive status;
// - realtime bytes (F8, FA, FB, FC, FE, FF) are delivered at once, anywhere, also inside
//   a message or SysEx, without disturbing it; F9 and FD are undefined and dropped;
// - SysEx (F0 ... F7) is assembled into a fixed buffer; one longer than the cap is dropped
//   (counted); a SysEx ended by any status other than F7 is dropped (counted), and that
//   status byte is then processed normally;
// - F4/F5 are undefined system common: dropped, and running status is cleared;
// - data bytes without a status are dropped (counted).
// Note-on with velocity 0 stays a note-on here (raw bytes); `midi_to_event` is the one
// place that turns it into a note-off. Allocation happens only in the constructor.
#pragma once

#include "input/event.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace mar {

struct MidiMessage {
  uint8_t bytes[3] = {0, 0, 0};      ///< status and data (without running status)
  uint8_t size = 0;                  ///< 1..3 for short messages; 0 for SysEx
  std::span<const uint8_t> sysex;    ///< F0 ... F7 when a SysEx; valid during the callback
  uint8_t status() const { return size ? bytes[0] : uint8_t(0xF0); }
  bool is_sysex() const { return size == 0; }
};

/// The MIDI 1.0 message type name used by the corpus vectors ("note_on", "clock", ...).
const char* midi_type_name(uint8_t status);
/// Number of data bytes that follow a status byte, or -1 for SysEx/undefined/realtime-without-data.
int midi_data_length(uint8_t status);

struct MidiStats {
  uint64_t messages = 0, dropped_bytes = 0, dropped_sysex = 0, oversize_sysex = 0;
};

class MidiStreamDecoder {
 public:
  explicit MidiStreamDecoder(size_t sysex_cap = 1024);

  /// Feeds bytes; calls `on(const MidiMessage&)` for each complete message.
  template <class F>
  void feed(std::span<const uint8_t> bytes, F&& on) {
    for (uint8_t b : bytes) feed_byte(b, on);
  }
  template <class F>
  void feed_byte(uint8_t b, F&& on) {
    MidiMessage m;
    if (step(b, m)) {
      ++stats_.messages;
      on(static_cast<const MidiMessage&>(m));
    }
  }
  /// Forgets any partial message, SysEx and running status (e.g. after a device reconnects).
  void reset();
  const MidiStats& stats() const { return stats_; }

 private:
  bool step(uint8_t b, MidiMessage& out);
  std::vector<uint8_t> sysex_;
  size_t sysex_len_ = 0;
  bool in_sysex_ = false, sysex_overflow_ = false;
  uint8_t running_ = 0;   ///< channel status for running status, 0 = none
  uint8_t status_ = 0;    ///< status of the message being assembled, 0 = none
  uint8_t data_[2] = {0, 0};
  int have_ = 0, need_ = 0;
  MidiStats stats_;
};

/// Turns a channel-voice message into an Event (note-on velocity 0 becomes note-off).
/// Returns false for system messages and SysEx, which the mapping does not bind.
bool midi_to_event(const MidiMessage& m, int64_t t_ns, uint16_t source, Event& out);

}  // namespace mar
