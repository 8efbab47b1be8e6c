// MIDI 1.0 byte streams (serial, ALSA raw): running status, real-time bytes inside
// messages, SysEx of any length against a small cap, and the events the mapping sees.
#include "fuzz_util.h"
#include "input/decoder.h"
#include "input/midi.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mar::MidiStreamDecoder d(64);
  d.feed(std::span<const uint8_t>(data, size), [](const mar::MidiMessage& m) {
    mar::Event e;
    (void)mar::midi_to_event(m, 0, 1, e);
  });
  // The same bytes as wire records through the decoder a connection makes.
  auto dec = mar::make_midi_decoder(mar::WireKind::MidiBytes, 1);
  for (size_t i = 0; i < size; i += mar::WireRecord::kMax) {
    const size_t n = std::min(size - i, mar::WireRecord::kMax);
    dec->feed(mar::WireRecord::make(int64_t(i), mar::WireKind::MidiBytes, {data + i, n}, 1), [](const mar::Event&) {});
  }
  return 0;
}
