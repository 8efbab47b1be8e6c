// USB-MIDI event packets (bulk IN transfers): 16 cables, every code index number, SysEx
// spread over packets, trailing partial packets; then the same bytes through the decoder.
#include "fuzz_util.h"
#include "input/decoder.h"
#include "input/usb_midi.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mar::UsbMidiDecoder d(64);
  d.feed(std::span<const uint8_t>(data, size), [](uint8_t, const mar::MidiMessage& m) {
    mar::Event e;
    (void)mar::midi_to_event(m, 0, 1, e);
    uint8_t packet[4];
    // Encoding a decoded message again is what the feedback path does.
    if (!m.is_sysex()) (void)mar::usb_midi_encode(0, {m.bytes, size_t(m.size)}, packet);
  });
  auto dec = mar::make_midi_decoder(mar::WireKind::UsbMidi, 1);
  for (size_t i = 0; i < size; i += 64) {
    const size_t n = std::min<size_t>(size - i, 64);
    dec->feed(mar::WireRecord::make(int64_t(i), mar::WireKind::UsbMidi, {data + i, n}, 1), [](const mar::Event&) {});
  }
  return 0;
}
