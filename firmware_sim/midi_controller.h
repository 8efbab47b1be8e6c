// A class-compliant USB-MIDI controller with the Korg nanoKONTROL2 layout (CC numbers as
// in Ardour's nanoKONTROL2 map): 8 faders CC 0-7, 8 knobs CC 16-23, solo 32-39, mute
// 48-55, record 64-71, transport (play 41, stop 42, rewind 43, forward 44, record 45,
// cycle 46, marker set 60, marker prev 61, marker next 62, track prev 58, track next 59),
// all on channel 1. It sends USB-MIDI event packets (CIN 0xB) on cable 0, one per value
// change, at most one per millisecond per control, 7-bit values; buttons send 127/0. As a
// clock source (a sequencer's, or a DJ controller's) it sends MIDI clock: 0xFA start half a tick
// before the line's time, then 24 0xF8 ticks a beat from that time at a scripted tempo, each off its time by up to `jitter` (uniform, seeded),
// and 0xFC stop:
//   0.0 clock 120 [jitter 0.001] [for 10]   (BPM; jitter and length in seconds)
#pragma once

#include "firmware_sim/sim_device.h"

namespace mar {

class MidiControllerSim : public SimDevice {
 public:
  const char* kind() const override { return "nanokontrol2"; }
  WireKind wire() const override { return WireKind::UsbMidi; }
  /// CC number of a control name ("fader1", "knob8", "solo3", "play", ...), or -1.
  static int cc_of(const std::string& control);
  /// Moves an absolute control (fader/knob) from its current position to `to` (0..1)
  /// over `dur_s` seconds starting at `t_s`, linearly.
  void move(const std::string& control, double t_s, double to, double dur_s);
  /// Presses a button at `t_s` and releases it `hold_s` later.
  void press(const std::string& control, double t_s, double hold_s);
  void send_cc(int64_t t_ns, int cc, int value);
  /// Start at `t_s`, ticks at `bpm` for `dur_s` seconds (each off by up to ±`jitter_s`), then stop.
  void clock(double t_s, double bpm, double jitter_s, double dur_s, uint32_t seed);
  void send_realtime(int64_t t_ns, uint8_t status);

 protected:
  Result<bool> action(double t, const std::vector<std::string>& w) override;

 private:
  int position_[128] = {};  ///< last sent value per CC
};

}  // namespace mar
