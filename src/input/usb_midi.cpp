#include "input/usb_midi.h"

namespace mar {

int usb_midi_cin_length(uint8_t cin) {
  switch (cin & 0xF) {
    case 0x2:
    case 0x6:
    case 0xC:
    case 0xD: return 2;
    case 0x5:
    case 0xF: return 1;
    default: return 3;
  }
}

UsbMidiPacket usb_midi_decode(const uint8_t packet[4]) {
  UsbMidiPacket p;
  p.cable = packet[0] >> 4;
  p.cin = packet[0] & 0xF;
  p.size = uint8_t(usb_midi_cin_length(p.cin));
  for (int i = 0; i < p.size; ++i) p.payload[i] = packet[1 + i];
  const uint8_t s = p.payload[0];
  switch (p.cin) {
    case 0x4: p.is_sysex = true; break;
    case 0x6:
    case 0x7: p.is_sysex = p.sysex_end = true; break;
    case 0x5: p.is_sysex = p.sysex_end = (s == 0xF7); break;
    case 0xF: p.is_sysex = s < 0x80; break;
    default: break;
  }
  p.sysex_start = p.is_sysex && s == 0xF0;
  return p;
}

const char* usb_midi_error_name(UsbMidiEncodeError e) {
  switch (e) {
    case UsbMidiEncodeError::None: return "None";
    case UsbMidiEncodeError::EmptyPayload: return "EmptyPayload";
    case UsbMidiEncodeError::InvalidPayloadSize: return "InvalidPayloadSize";
    case UsbMidiEncodeError::InvalidPayloadStatus: return "InvalidPayloadStatus";
  }
  return "?";
}

UsbMidiEncodeError usb_midi_encode(uint8_t cable, std::span<const uint8_t> pl, uint8_t packet[4]) {
  if (pl.empty()) return UsbMidiEncodeError::EmptyPayload;
  packet[1] = packet[2] = packet[3] = 0;
  const uint8_t s = pl[0];
  uint8_t cin = 0;
  size_t n = 0;
  if (s == 0xF0 || s == 0xF7 || s < 0x80) {  // SysEx start, continuation or end
    for (size_t i = 0; i < pl.size() && i < 3; ++i)
      if (pl[i] == 0xF7) {
        cin = uint8_t(0x5 + i);
        n = i + 1;
        break;
      }
    if (n == 0) {
      if (pl.size() >= 3) {
        cin = 0x4;
        n = 3;
      } else if (pl.size() == 1 && s < 0x80) {
        cin = 0xF;
        n = 1;
      } else {
        return UsbMidiEncodeError::InvalidPayloadSize;
      }
    }
  } else if (s == 0xF4 || s == 0xF5) {
    return UsbMidiEncodeError::InvalidPayloadStatus;
  } else if (s >= 0xF8) {
    cin = 0xF;
    n = 1;
  } else {
    const int len = 1 + midi_data_length(s);
    if (pl.size() < size_t(len)) return UsbMidiEncodeError::InvalidPayloadSize;
    n = size_t(len);
    if (s < 0xF0)
      cin = s >> 4;
    else
      cin = s == 0xF6 ? 0x5 : uint8_t(len);  // F1/F3 -> 2, F2 -> 3
  }
  for (size_t i = 0; i < n; ++i) {
    if (i > 0 && pl[i] >= 0x80 && !(pl[i] == 0xF7 && cin >= 0x5 && cin <= 0x7))
      return UsbMidiEncodeError::InvalidPayloadStatus;
    packet[1 + i] = pl[i];
  }
  packet[0] = uint8_t((cable & 0xF) << 4 | cin);
  return UsbMidiEncodeError::None;
}

UsbMidiDecoder::UsbMidiDecoder(size_t sysex_cap) : sysex_cap_(sysex_cap) {
  for (auto& c : cables_) c = std::make_unique<MidiStreamDecoder>(sysex_cap_);
}

MidiStreamDecoder& UsbMidiDecoder::cable(uint8_t c) { return *cables_[c & 0xF]; }

void UsbMidiDecoder::reset() {
  for (auto& c : cables_)
    c->reset();
}

}  // namespace mar
