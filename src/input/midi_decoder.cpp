// USB-MIDI packets or a MIDI 1.0 byte stream -> Events.
#include "input/decoder.h"
#include "input/midi.h"
#include "input/usb_midi.h"

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
      if (midi_to_event(m, r.t_ns, source(), e)) out.push(e);
    };
    if (kind() == WireKind::UsbMidi) usb_.feed(r.bytes(), [&](uint8_t, const MidiMessage& m) { on(m); });
    else stream_.feed(r.bytes(), on);
    if (dropped() != before) malformed();
  }
  uint64_t dropped() const { return kind() == WireKind::UsbMidi ? usb_.dropped_bytes() : stream_.stats().dropped_bytes; }
  UsbMidiDecoder usb_;
  MidiStreamDecoder stream_;
};

}  // namespace

std::unique_ptr<Decoder> make_midi_decoder(WireKind k, uint16_t source) { return std::make_unique<MidiDecoder>(k, source); }

}  // namespace mar
