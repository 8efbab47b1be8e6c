// Wire records -> Events. One small decoder type per wire format (USB-MIDI packets, a MIDI
// byte stream, HID reports, GPIO edges, evdev events, OSC messages, SDL controls); the
// records may come from hardware, a simulated device or a recording, and the decoder is
// the same. A decoder is made from a DecoderConfig, which a device states when it opens
// (a HID device's report descriptor, a tablet's axis ranges) and recordings store, so a
// replay re-decodes the very bytes the show read.
#pragma once

#include "base/result.h"
#include "input/hid.h"
#include "input/voice.h"
#include "input/wire.h"

#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace mar {

/// A frame's decoded events.
using EventSink = FixedSink<Event>;

struct WireStats {
  uint64_t records = 0, events = 0, malformed = 0;
};

struct GpioLayout {
  struct Encoder {
    int line_a = 0, line_b = 1, steps_per_detent = 4;
  };
  std::vector<Encoder> encoders;  ///< EncoderDelta number = index + 1
  std::vector<int> buttons;       ///< Button number = index + 1 (active low: 0 = pressed)
  int64_t debounce_ns = 0;        ///< encoder stable-time filter and button lockout
};

/// An evdev absolute axis: its code and range (libevdev's absinfo).
struct EvdevAxis {
  uint16_t code = 0;
  int32_t min = 0, max = 0;
};

/// Everything a decoder needs besides the records.
struct DecoderConfig {
  WireKind kind = WireKind::UsbMidi;
  std::vector<uint8_t> hid_descriptor;   ///< HidReport: the report descriptor bytes
  GpioLayout gpio;                       ///< GpioEdge: line roles and debounce
  std::vector<EvdevAxis> axes;           ///< EvdevEvent: absolute axis ranges
  std::vector<std::string> osc_patterns; ///< OscMessage: bound address patterns (number = 0xFF000000 | index)
  int32_t audio_rate = 0;                ///< AudioPcm: samples per second
  /// AudioPcm: a voice's F1, F2 for a, i, u, e, o (Hz; 0: the default templates), input/voice.h.
  std::array<std::array<double, 2>, 5> voice{};

  /// A compact binary form (what recordings store); parse() reads it back.
  std::vector<uint8_t> serialize() const;
  static Result<DecoderConfig> parse(std::span<const uint8_t> bytes);
};

class Decoder {
 public:
  virtual ~Decoder() = default;
  /// Decodes one record into `out`. Allocates nothing. A record of another kind, or one
  /// the format rejects, is counted as malformed and dropped.
  void feed(const WireRecord& r, EventSink& out) {
    ++stats_.records;
    const size_t n = out.n;
    if (r.kind != kind_) ++stats_.malformed;
    else decode(r, out);
    stats_.events += out.n - n;
  }
  /// Emits what time alone produces (debounced GPIO levels that became stable by `now_ns`).
  void settle(int64_t now_ns, EventSink& out) {
    const size_t n = out.n;
    settle_at(now_ns, out);
    stats_.events += out.n - n;
  }
  /// The same, calling `on(const Event&)` per event (tests, tools).
  template <class F>
  void feed(const WireRecord& r, F&& on) {
    Event buf[256];
    EventSink s{buf, std::size(buf)};
    feed(r, s);
    for (size_t i = 0; i < s.n; ++i) on(static_cast<const Event&>(buf[i]));
  }
  template <class F>
  void settle(int64_t now_ns, F&& on) {
    Event buf[256];
    EventSink s{buf, std::size(buf)};
    settle(now_ns, s);
    for (size_t i = 0; i < s.n; ++i) on(static_cast<const Event&>(buf[i]));
  }
  const WireStats& stats() const { return stats_; }
  /// The last whole SysEx decoded (MIDI; empty for other kinds), and how many there have been:
  /// a device's answer to a request (app/loop/leds.h). Valid until the next feed().
  virtual std::span<const uint8_t> last_sysex(uint64_t& count) const {
    count = 0;
    return {};
  }
  WireKind kind() const { return kind_; }
  uint16_t source() const { return source_; }

 protected:
  Decoder(WireKind k, uint16_t source) : kind_(k), source_(source) {}
  virtual void decode(const WireRecord& r, EventSink& out) = 0;
  virtual void settle_at(int64_t, EventSink&) {}
  void malformed() { ++stats_.malformed; }
  Event event(int64_t t, ControlKind k) const {
    Event e;
    e.t_ns = t;
    e.source = source_;
    e.kind = k;
    return e;
  }

 private:
  WireKind kind_;
  uint16_t source_;
  WireStats stats_;
};

/// The decoder for `c`; nullptr with `error` set when the configuration is unusable
/// (a HID descriptor the parser rejects, an unknown kind).
std::unique_ptr<Decoder> make_decoder(const DecoderConfig& c, uint16_t source, std::string* error = nullptr);

// The decoder types (one file each).
std::unique_ptr<Decoder> make_midi_decoder(WireKind k, uint16_t source);  ///< UsbMidi or MidiBytes
std::unique_ptr<Decoder> make_hid_decoder(HidDescriptor d, uint16_t source);
std::unique_ptr<Decoder> make_gpio_decoder(GpioLayout layout, uint16_t source);
std::unique_ptr<Decoder> make_evdev_decoder(std::vector<EvdevAxis> axes, uint16_t source);
std::unique_ptr<Decoder> make_osc_decoder(std::vector<std::string> patterns, uint16_t source);
std::unique_ptr<Decoder> make_sdl_decoder(uint16_t source);
/// AudioPcm: nullptr for a sample rate outside 4..192 kHz.
std::unique_ptr<Decoder> make_audio_decoder(const DecoderConfig& c, uint16_t source);

/// The usages of a voice's controls (audio_decoder.cpp): level 0..1000 over -60..0 dBFS, a
/// button per viseme (closed, a, i, u, e, o) held while it shows, an onset press.
namespace voice_usage {
constexpr uint32_t kLevel = 0xFFA00001u, kOnset = 0xFFA00002u, kViseme = 0xFFA00010u;
constexpr uint32_t viseme(Viseme v) { return kViseme + uint32_t(v); }
}  // namespace voice_usage

// Records as the backends write them (and tests build them).
WireRecord sdl_record(int64_t t, SdlWhat what, uint8_t index, int32_t value, int32_t lo, int32_t hi, uint16_t source);
WireRecord evdev_record(int64_t t, uint16_t type, uint16_t code, int32_t value, uint16_t source);
/// Up to 48 samples of mono 16-bit PCM as one record.
WireRecord audio_record(int64_t t, std::span<const int16_t> pcm, uint16_t source);

}  // namespace mar
