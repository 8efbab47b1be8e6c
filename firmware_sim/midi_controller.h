// Class-compliant USB-MIDI controllers, each with its maker's factory layout and LED behaviour
// (firmware_sim/midi_models.cpp):
//   nanokontrol2       Korg nanoKONTROL2, CC mode: 8 faders CC 0-7, knobs 16-23, solo 32-39, mute
//                      48-55, rec 64-71, transport (play 41, stop 42, rewind 43, forward 44, record
//                      45, cycle 46, marker set 60 / prev 61 / next 62, track prev 58 / next 59),
//                      channel 1. Its LEDs follow CCs on the same numbers only in the External LED
//                      mode, a byte of its scene (input/korg_scene.h). It answers Korg's search
//                      device, scene dump request, scene data (ACK) and scene write request as the
//                      unit does; the script's `ledmode external` stands for a unit whose stored
//                      scene was set so in the Korg Kontrol Editor.
//   apc_mini_mk2       Akai APC mini mk2: an 8x8 pad grid, notes 0-63 (0 bottom left; named
//                      pad_rRcC from the top left), track 1-8 notes 100-107, scene 1-8 notes
//                      112-119, shift 122, faders 1-8 CC 48-55 and master CC 56, channel 1. A pad
//                      lights by a note-on of its note: velocity a colour of the palette, the channel
//                      its brightness (1-7: 10-100 %, 8-11 pulsing, 12-16 blinking); track and scene
//                      LEDs: velocity 0 off, 1 on, 2 blinking.
//   midimix            Akai MIDImix: per strip three knobs (CC 16-18, 20-22, 24-26, 28-30, 46-48,
//                      50-52, 54-56, 58-60), a fader (CC 19, 23, 27, 31, 49, 53, 57, 61), mute notes
//                      1, 4, ... 22, rec arm 3, 6, ... 24 (solo is shift + mute: 2, 5, ... 23), master
//                      CC 62, bank left 25, right 26, solo 27, channel 1. Mute, rec arm and bank
//                      LEDs light by a note-on of their note, velocity 127 (0: off).
//   launch_control_xl  Novation Launch Control XL, factory template 1 (channel 9): send A knobs
//                      CC 13-20, send B 29-36, pan 49-56, faders 77-84, track focus buttons notes
//                      41-44, 57-60, track control 73-76, 89-92, device 105, mute 106, solo 107, record
//                      arm 108, up/down CC 104/105, left/right CC 106/107. A button lights by a
//                      note-on of its note on the template's channel: velocity = 16 x green + red +
//                      12 (each 0-3: off 12, red 15, amber 63, yellow 62, green 60).
//   xtouch_mini        Behringer X-Touch Mini, standard mode, layer A (channel 11): encoders CC 1-8,
//                      their pushes notes 0-7, buttons notes 8-23 (upper row 8-15), fader CC 9. It
//                      takes remote LED control on its global channel (1): button LED k (0-15) by a
//                      note-on of note k (velocity 0 off, 1 on, 2 blinking), an encoder's ring mode
//                      by CC 1-8 (0 single, 1 pan, 2 fan, 3 spread, 4 trim) and its ring by CC 9-16
//                      (0 off, 1-13 one LED, 14-26 blinking, 27 all).
//   beatstep           Arturia BeatStep, factory preset: encoders 1-16 CC 10, 74, 71, 76, 77, 93,
//                      73, 75, 114, 18, 19, 16, 17, 91, 79, 72, the big knob CC 7, pads 1-8 notes
//                      44-51 and 9-16 notes 36-43, channel 1. A pad's LED is set by SysEx
//                      F0 00 20 6B 7F 42 02 00 10 7p vv F7 (p: pad - 1; vv 00 off, 01 red, 10 blue,
//                      11 both).
// Each sends USB-MIDI event packets on cable 0, one per value change, at most one per
// millisecond per control, 7-bit values; buttons 127/0 (notes: note-on 127, note-off). As a
// clock source it sends MIDI clock: 0xFA start half a tick before the line's time, then 24 0xF8
// ticks a beat from that time at a scripted tempo, each off its time by up to `jitter`
// (uniform, seeded), and 0xFC stop:
//   0.0 clock 120 [jitter 0.001] [for 10]   (BPM; jitter and length in seconds)
// What it is sent (receive()) sets its LEDs as the real one would; leds() says what is lit.
#pragma once

#include "firmware_sim/sim_device.h"
#include "input/korg_scene.h"

#include <span>
#include <string>
#include <vector>

namespace mar {

/// One control of a MIDI controller's factory layout.
struct MidiControl {
  std::string name;
  bool note = false;  ///< a note (a button or pad) rather than a CC
  int number = 0;
  int channel = 0;    ///< 0-15
};

/// A controller model's layout, by kind ("nanokontrol2", "apc_mini_mk2", ...); nullptr if unknown.
struct MidiModel;
const MidiModel* midi_model(const std::string& kind);
/// The kinds there are ("nanokontrol2, apc_mini_mk2, ...").
std::string midi_model_names();

class MidiControllerSim : public SimDevice {
 public:
  explicit MidiControllerSim(const std::string& kind = "nanokontrol2");
  const char* kind() const override;
  WireKind wire() const override { return WireKind::UsbMidi; }
  /// CC number of a nanoKONTROL2 control name ("fader1", "knob8", "solo3", "play", ...), or -1.
  static int cc_of(const std::string& control);
  /// This model's controls, and one by name (nullptr if it has none).
  const std::vector<MidiControl>& controls() const;
  const MidiControl* control(const std::string& name) const;
  /// Moves an absolute control (fader/knob) from its current position to `to` (0..1)
  /// over `dur_s` seconds starting at `t_s`, linearly.
  void move(const std::string& control, double t_s, double to, double dur_s);
  /// Presses a button at `t_s` and releases it `hold_s` later; a pad's note-on carries
  /// `velocity` (1..127; a button's is 127 whatever it is given).
  void press(const std::string& control, double t_s, double hold_s, int velocity = 127);
  /// A pad's own pressure (polyphonic key pressure, 0..1) from its current value to `to` over
  /// `dur_s` seconds, and the channel's pressure (aftertouch) the same way.
  void pressure(const std::string& control, double t_s, double to, double dur_s);
  void aftertouch(double t_s, double to, double dur_s, int channel = 0);
  void send_cc(int64_t t_ns, int cc, int value, int channel = 0);
  /// Start at `t_s`, ticks at `bpm` for `dur_s` seconds (each off by up to ±`jitter_s`), then stop.
  void clock(double t_s, double bpm, double jitter_s, double dur_s, uint32_t seed);
  void send_realtime(int64_t t_ns, uint8_t status);

  /// MIDI the host sent it (whole messages, SysEx included): its LEDs follow as the model's.
  /// Allocation-free. Returns false for a message that sets no LED (counted).
  bool receive(std::span<const uint8_t> message) override;
  /// What is lit: per control with an LED, the last value that set it (-1: never set). For the
  /// APC mini mk2's pads, led_channel() is the brightness channel it came on.
  int led(const std::string& name) const;
  int led_channel(const std::string& name) const;
  /// nanoKONTROL2: whether its current scene's LED mode is External, and its stored one's.
  bool external_leds() const { return scene_[korg::kLedModeAt] == 1; }
  bool stored_external_leds() const { return stored_[korg::kLedModeAt] == 1; }
  /// "name=value ..." of every LED set, in layout order (rings: ringN).
  std::string leds() const override;
  uint64_t ignored() const { return ignored_; }

 protected:
  Result<bool> action(double t, const std::vector<std::string>& w) override;

 private:
  void send(int64_t t_ns, const MidiControl& c, int value);
  void send_message(int64_t t_ns, std::span<const uint8_t> msg);
  /// One value sweep (`from` to `to` over `dur_s`, one message per 7-bit change) through `emit_value`.
  template <class F>
  void sweep(double t_s, int from, int to, double dur_s, F emit_value);
  int pressure_[16][128] = {};  ///< last polyphonic pressure per channel and note
  int aftertouch_[16] = {};     ///< last channel pressure
  bool set_led(int index, int value, int channel);
  const MidiModel* model_;
  int position_[16][128] = {};  ///< last value sent per channel and CC
  std::vector<int> led_, led_channel_;  ///< per control (layout order), then the rings
  bool korg(std::span<const uint8_t> sysex);  ///< nanoKONTROL2: a scene request, answered
  korg::Scene scene_ = korg::factory_scene(), stored_ = scene_;  ///< nanoKONTROL2: current and written scene
  uint64_t ignored_ = 0;
};

}  // namespace mar
