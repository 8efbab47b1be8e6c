// USB-MIDI packets or a MIDI 1.0 byte stream -> Events; MIDI clock -> beat and bar phases
// (input/midi_clock.h), an event of each at every tick once the tempo is known.
#include "input/decoder.h"
#include "input/midi.h"
#include "input/midi_clock.h"
#include "input/usb_midi.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace mar {
namespace {

class MidiDecoder final : public Decoder {
 public:
  MidiDecoder(WireKind k, uint16_t source) : Decoder(k, source) {}

 private:
  void decode(const WireRecord& r, EventSink& out) override {
    const uint64_t before = dropped();
    auto on = [&](const MidiMessage& m) {
      Event e;
      if (m.is_sysex()) {
        sysex_len_ = std::min(m.sysex.size(), sysex_.size());
        std::copy_n(m.sysex.begin(), sysex_len_, sysex_.begin());
        ++sysex_count_;
      } else if (midi_to_event(m, r.t_ns, source(), e)) {
        out.push(e);
      } else if (!m.is_sysex() && m.bytes[0] >= 0xF8 && clock_.feed(m.bytes[0], r.t_ns) && clock_.locked()) {
        // Where the beat is, on the fitted line at this tick: the tick's own jitter left out.
        const int64_t at = int64_t(std::llround(clock_.last_tick_time_ns()));
        for (uint32_t which : {kClockTempo, kClockBeat, kClockBar}) {
          e = Event{};
          e.t_ns = r.t_ns;
          e.source = source();
          e.kind = ControlKind::ClockPhase;
          e.number = which;
          e.lo = 0;
          e.hi = kClockPhaseMax;
          if (which == kClockTempo) e.value = int32_t(std::clamp(std::lround(clock_.bpm() * 1000), 0L, long(kClockPhaseMax)));
          else e.value = int32_t(std::lround((which == kClockBeat ? clock_.beat_phase(at) : clock_.bar_phase(at)) * kClockPhaseMax)) % kClockPhaseMax;
          out.push(e);
        }
      }
    };
    if (kind() == WireKind::UsbMidi) usb_.feed(r.bytes(), [&](uint8_t, const MidiMessage& m) { on(m); });
    else stream_.feed(r.bytes(), on);
    if (dropped() != before) malformed();
  }
  std::span<const uint8_t> last_sysex(uint64_t& count) const override {
    count = sysex_count_;
    return {sysex_.data(), sysex_len_};
  }
  uint64_t dropped() const { return kind() == WireKind::UsbMidi ? usb_.dropped_bytes() : stream_.stats().dropped_bytes; }
  UsbMidiDecoder usb_;
  MidiStreamDecoder stream_;
  MidiClock clock_;
  std::array<uint8_t, 1024> sysex_{};  ///< (the stream decoders' cap)
  size_t sysex_len_ = 0;
  uint64_t sysex_count_ = 0;
};

}  // namespace

std::unique_ptr<Decoder> make_midi_decoder(WireKind k, uint16_t source) { return std::make_unique<MidiDecoder>(k, source); }

}  // namespace mar
