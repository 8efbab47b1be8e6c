// The device-agnostic input event: what every decoder produces and the mapping consumes.
#pragma once

#include <cstdint>

namespace mar {

/// What kind of control an event comes from. `number` and `channel` are read per kind.
enum class ControlKind : uint8_t {
  None,
  MidiNoteOn,        ///< channel, number = note, value = velocity 1..127
  MidiNoteOff,       ///< channel, number = note, value = release velocity (note-on vel 0 lands here)
  MidiCC,            ///< channel, number = controller 0..127, value 0..127
  MidiPitchBend,     ///< channel, value 0..16383 (centre 8192)
  MidiProgram,       ///< channel, value = program
  MidiChannelPressure,
  MidiPolyPressure,  ///< channel, number = note
  HidValue,          ///< number = usage (page << 16 | id), channel = collection index, value = logical
  EncoderDelta,      ///< number = encoder index, value = signed detents (or quarter steps)
  Button,            ///< number = button index, value 1 pressed / 0 released
  PointerX,          ///< value in [lo, hi]
  PointerY,
  Pressure,
  ClockPhase,        ///< MIDI clock: number = kClockBeat | kClockBar, value = phase in 0..kClockPhaseMax
};

constexpr uint32_t kClockBeat = 0, kClockBar = 1;
/// A clock tick's tempo: value = BPM x 1000 (range 0..kClockPhaseMax), sent before its phases.
constexpr uint32_t kClockTempo = 2;
constexpr int32_t kClockPhaseMax = 1000000;

/// One decoded control change. `t_ns` is the device timestamp on the loop's monotonic clock.
struct Event {
  int64_t t_ns = 0;
  uint16_t source = 0;  ///< device index in the show
  ControlKind kind = ControlKind::None;
  uint8_t channel = 0;
  uint32_t number = 0;
  int32_t value = 0;
  int32_t lo = 0, hi = 0;  ///< logical range of an absolute control (lo == hi: relative)
};

/// An absolute value as a fraction of its logical range (0 when the range is empty), in double
/// precision: a range of INT32_MIN..INT32_MAX does not overflow.
inline double normalized(const Event& e) {
  return e.hi > e.lo ? (double(e.value) - double(e.lo)) / (double(e.hi) - double(e.lo)) : 0.0;
}

/// now − since ≥ d, without overflow: device timestamps are whatever a device or a recording
/// says, up to the int64 limits.
inline bool elapsed_at_least(int64_t now, int64_t since, int64_t d) {
  int64_t diff = 0;
  if (__builtin_sub_overflow(now, since, &diff)) return now > since;
  return diff >= d;
}

const char* control_kind_name(ControlKind k);

}  // namespace mar
