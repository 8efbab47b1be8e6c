#include "app/loop/learn.h"

namespace mar {

bool learn_control(std::span<const Event> events, const ShowConfig& show, Learned& out) {
  for (const Event& e : events) {
    if (e.source >= show.devices.size()) continue;
    const ShowDevice& d = show.devices[e.source];
    ControlSpec spec;
    switch (e.kind) {
      case ControlKind::MidiCC: spec.kind = ControlSpec::CC; break;
      case ControlKind::MidiNoteOn: spec.kind = ControlSpec::Note; break;
      case ControlKind::MidiPitchBend: spec.kind = ControlSpec::PitchBend; break;
      case ControlKind::MidiChannelPressure: spec.kind = ControlSpec::Aftertouch; break;
      case ControlKind::MidiPolyPressure: spec.kind = ControlSpec::PolyPressure; break;
      case ControlKind::EncoderDelta:
        // A GPIO encoder is "encoder N"; a HID relative axis (jog wheel, dial) is its usage.
        spec.kind = d.sim == "knob_box" || d.type == "gpio" ? ControlSpec::Encoder : ControlSpec::Hid;
        break;
      case ControlKind::Button: spec.kind = ControlSpec::GpioButton; break;
      case ControlKind::HidValue: spec.kind = ControlSpec::Hid; break;
      default: continue;
    }
    spec.number = e.number;
    if (e.kind == ControlKind::MidiCC || e.kind == ControlKind::MidiNoteOn || e.kind == ControlKind::MidiPitchBend ||
        e.kind == ControlKind::MidiChannelPressure || e.kind == ControlKind::MidiPolyPressure)
      spec.channel = e.channel;
    out.device = e.source;
    out.control = format_control(spec);
    return true;
  }
  return false;
}

}  // namespace mar
