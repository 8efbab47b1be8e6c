// One device's wire data -> Events: the decoder a device's records run through, whether
// they come from hardware, a simulated device or a recording.
#pragma once

#include "input/hid.h"
#include "input/quadrature.h"
#include "input/usb_midi.h"
#include "input/wire.h"

#include <memory>
#include <vector>

namespace mar {

struct GpioLayout {
  struct Encoder {
    int line_a = 0, line_b = 1, steps_per_detent = 4;
  };
  std::vector<Encoder> encoders;  ///< EncoderDelta number = index + 1
  std::vector<int> buttons;       ///< Button number = index + 1 (active low: 0 = pressed)
  int64_t debounce_ns = 0;        ///< encoder stable-time filter and button lockout
};

struct WireStats {
  uint64_t records = 0, events = 0, malformed = 0;
};

class WireDecoder {
 public:
  static std::unique_ptr<WireDecoder> midi(WireKind k, uint16_t source);
  static std::unique_ptr<WireDecoder> hid(HidDescriptor d, uint16_t source);
  static std::unique_ptr<WireDecoder> gpio(GpioLayout layout, uint16_t source);
  /// Events already decoded by a hardware backend (WireKind::Event records).
  static std::unique_ptr<WireDecoder> events(uint16_t source);

  /// Decodes one record; calls `on(const Event&)` per event. Allocates nothing.
  template <class F>
  void feed(const WireRecord& r, F&& on) {
    ++stats_.records;
    n_ = 0;
    decode(r);
    flush(on);
  }
  /// Applies debounced GPIO levels that have become stable by `now_ns`.
  template <class F>
  void settle(int64_t now_ns, F&& on) {
    n_ = 0;
    settle_gpio(now_ns);
    flush(on);
  }
  const WireStats& stats() const { return stats_; }
  void reset();

 private:
  template <class F>
  void flush(F& on) {
    for (size_t i = 0; i < n_; ++i) on(static_cast<const Event&>(out_[i]));
    stats_.events += n_;
  }
  void decode(const WireRecord& r);
  void settle_gpio(int64_t now);
  void push(const Event& e);
  void encoder_events(int64_t t);

  WireKind kind_ = WireKind::UsbMidi;
  uint16_t source_ = 0;
  std::unique_ptr<UsbMidiDecoder> usb_;
  std::unique_ptr<MidiStreamDecoder> stream_;
  HidDescriptor hid_;
  std::vector<std::vector<uint8_t>> last_;  ///< previous report per descriptor report
  std::vector<char> seen_;
  GpioLayout gpio_;
  std::vector<QuadratureDecoder> quad_;
  std::vector<int> button_level_;
  std::vector<int64_t> button_t_;
  std::vector<int> line_role_;  ///< per line: encoder*2 + (0|1), or -(button+1), or INT_MIN
  Event out_[256];
  size_t n_ = 0;
  WireStats stats_;
};

}  // namespace mar
