// The factory layouts of the simulated MIDI controllers (firmware_sim/midi_controller.h says
// where each comes from). Internal to the simulator.
#pragma once

#include "firmware_sim/midi_controller.h"

namespace mar {

enum class LedProtocol { NanoKontrol2, ApcMiniMk2, MidiMix, LaunchControlXl, XTouchMini, BeatStep };

struct MidiModel {
  const char* kind;
  LedProtocol leds;
  std::vector<MidiControl> controls;
  int rings = 0;  ///< encoder LED rings (X-Touch Mini), after the controls in the LED state
};

}  // namespace mar
