#include "input/midi.h"

namespace mar {

const char* control_kind_name(ControlKind k) {
  switch (k) {
    case ControlKind::None: return "none";
    case ControlKind::MidiNoteOn: return "note_on";
    case ControlKind::MidiNoteOff: return "note_off";
    case ControlKind::MidiCC: return "cc";
    case ControlKind::MidiPitchBend: return "pitch_bend";
    case ControlKind::MidiProgram: return "program";
    case ControlKind::MidiChannelPressure: return "channel_pressure";
    case ControlKind::MidiPolyPressure: return "poly_pressure";
    case ControlKind::HidValue: return "hid";
    case ControlKind::EncoderDelta: return "encoder";
    case ControlKind::Button: return "button";
    case ControlKind::PointerX: return "pointer_x";
    case ControlKind::PointerY: return "pointer_y";
    case ControlKind::Pressure: return "pressure";
    case ControlKind::ClockPhase: return "clock_phase";
  }
  return "?";
}

const char* midi_type_name(uint8_t s) {
  switch (s & 0xF0) {
    case 0x80: return "note_off";
    case 0x90: return "note_on";
    case 0xA0: return "poly_aftertouch";
    case 0xB0: return "control_change";
    case 0xC0: return "program_change";
    case 0xD0: return "channel_aftertouch";
    case 0xE0: return "pitch_bend";
    default: break;
  }
  switch (s) {
    case 0xF0: return "sysex";
    case 0xF1: return "mtc_quarter_frame";
    case 0xF2: return "song_position";
    case 0xF3: return "song_select";
    case 0xF6: return "tune_request";
    case 0xF8: return "clock";
    case 0xFA: return "start";
    case 0xFB: return "continue";
    case 0xFC: return "stop";
    case 0xFE: return "active_sensing";
    case 0xFF: return "reset";
    default: return "undefined";
  }
}

int midi_data_length(uint8_t s) {
  if (s < 0x80) return -1;
  switch (s & 0xF0) {
    case 0xC0:
    case 0xD0: return 1;
    case 0xF0: break;
    default: return 2;
  }
  switch (s) {
    case 0xF1:
    case 0xF3: return 1;
    case 0xF2: return 2;
    case 0xF6:
    case 0xF8:
    case 0xFA:
    case 0xFB:
    case 0xFC:
    case 0xFE:
    case 0xFF: return 0;
    default: return -1;
  }
}

MidiStreamDecoder::MidiStreamDecoder(size_t sysex_cap) : sysex_(sysex_cap < 2 ? 2 : sysex_cap) {}

void MidiStreamDecoder::reset() {
  in_sysex_ = sysex_overflow_ = false;
  sysex_len_ = 0;
  running_ = status_ = 0;
  have_ = need_ = 0;
}

bool MidiStreamDecoder::step(uint8_t b, MidiMessage& out) {
  if (b >= 0xF8) {  // realtime: anywhere, state untouched
    if (b == 0xF9 || b == 0xFD) {
      ++stats_.dropped_bytes;
      return false;
    }
    out.bytes[0] = b;
    out.size = 1;
    return true;
  }
  if (in_sysex_) {
    if (b < 0x80) {
      if (sysex_len_ < sysex_.size() - 1)
        sysex_[sysex_len_++] = b;
      else
        sysex_overflow_ = true;
      return false;
    }
    in_sysex_ = false;
    if (b == 0xF7) {
      if (sysex_overflow_) {
        ++stats_.oversize_sysex;
        return false;
      }
      sysex_[sysex_len_++] = 0xF7;
      out.size = 0;
      out.sysex = std::span<const uint8_t>(sysex_.data(), sysex_len_);
      return true;
    }
    ++stats_.dropped_sysex;  // unterminated: dropped; b is processed below
  }
  if (b >= 0x80) {
    if (status_ != 0) ++stats_.dropped_bytes;  // abandoned partial message
    status_ = 0;
    have_ = 0;
    if (b < 0xF0) {
      running_ = status_ = b;
      need_ = midi_data_length(b);
      return false;
    }
    running_ = 0;  // system common and exclusive clear running status
    switch (b) {
      case 0xF0:
        in_sysex_ = true;
        sysex_overflow_ = false;
        sysex_[0] = 0xF0;
        sysex_len_ = 1;
        return false;
      case 0xF1:
      case 0xF2:
      case 0xF3:
        status_ = b;
        need_ = midi_data_length(b);
        return false;
      case 0xF6:
        out.bytes[0] = b;
        out.size = 1;
        return true;
      default:  // F4, F5 undefined; F7 without a SysEx
        ++stats_.dropped_bytes;
        return false;
    }
  }
  if (status_ == 0) {
    if (running_ == 0) {
      ++stats_.dropped_bytes;
      return false;
    }
    status_ = running_;
    need_ = midi_data_length(running_);
    have_ = 0;
  }
  data_[have_++] = b;
  if (have_ < need_) return false;
  out.bytes[0] = status_;
  out.bytes[1] = data_[0];
  out.bytes[2] = need_ > 1 ? data_[1] : 0;
  out.size = uint8_t(1 + need_);
  status_ = 0;
  have_ = 0;
  return true;
}

bool midi_to_event(const MidiMessage& m, int64_t t_ns, uint16_t source, Event& e) {
  if (m.is_sysex() || m.bytes[0] >= 0xF0) return false;
  const uint8_t type = m.bytes[0] & 0xF0;
  e = Event{};
  e.t_ns = t_ns;
  e.source = source;
  e.channel = m.bytes[0] & 0x0F;
  e.lo = 0;
  e.hi = 127;
  switch (type) {
    case 0x90:
      e.kind = m.bytes[2] == 0 ? ControlKind::MidiNoteOff : ControlKind::MidiNoteOn;
      e.number = m.bytes[1];
      e.value = m.bytes[2];
      break;
    case 0x80:
      e.kind = ControlKind::MidiNoteOff;
      e.number = m.bytes[1];
      e.value = m.bytes[2];
      break;
    case 0xA0:
      e.kind = ControlKind::MidiPolyPressure;
      e.number = m.bytes[1];
      e.value = m.bytes[2];
      break;
    case 0xB0:
      e.kind = ControlKind::MidiCC;
      e.number = m.bytes[1];
      e.value = m.bytes[2];
      break;
    case 0xC0:
      e.kind = ControlKind::MidiProgram;
      e.value = m.bytes[1];
      break;
    case 0xD0:
      e.kind = ControlKind::MidiChannelPressure;
      e.value = m.bytes[1];
      break;
    default:  // 0xE0
      e.kind = ControlKind::MidiPitchBend;
      e.value = m.bytes[1] | (m.bytes[2] << 7);
      e.hi = 16383;
      break;
  }
  return true;
}

}  // namespace mar
