#include "firmware_sim/midi_models.h"

#include <memory>
#include <string>

namespace mar {
namespace {

void add(std::vector<MidiControl>& v, const std::string& name, bool note, int number, int channel = 0) {
  v.push_back({name, note, number, channel});
}
void row(std::vector<MidiControl>& v, const std::string& prefix, bool note, std::initializer_list<int> numbers, int channel = 0) {
  int i = 1;
  for (int n : numbers) add(v, prefix + std::to_string(i++), note, n, channel);
}

MidiModel nanokontrol2() {
  MidiModel m{"nanokontrol2", LedProtocol::NanoKontrol2, {}, 0};
  row(m.controls, "fader", false, {0, 1, 2, 3, 4, 5, 6, 7});
  row(m.controls, "knob", false, {16, 17, 18, 19, 20, 21, 22, 23});
  row(m.controls, "solo", false, {32, 33, 34, 35, 36, 37, 38, 39});
  row(m.controls, "mute", false, {48, 49, 50, 51, 52, 53, 54, 55});
  row(m.controls, "rec", false, {64, 65, 66, 67, 68, 69, 70, 71});
  for (auto [n, cc] : {std::pair{"play", 41}, {"stop", 42}, {"rewind", 43}, {"forward", 44}, {"record", 45}, {"cycle", 46},
                       {"marker_set", 60}, {"marker_prev", 61}, {"marker_next", 62}, {"track_prev", 58}, {"track_next", 59}})
    add(m.controls, n, false, cc);
  return m;
}

MidiModel apc_mini_mk2() {
  MidiModel m{"apc_mini_mk2", LedProtocol::ApcMiniMk2, {}, 0};
  for (int r = 1; r <= 8; ++r)  // row 1 is the top: notes 56-63; row 8 the bottom: 0-7
    for (int c = 1; c <= 8; ++c) add(m.controls, "pad_r" + std::to_string(r) + "c" + std::to_string(c), true, (8 - r) * 8 + c - 1);
  row(m.controls, "track", true, {100, 101, 102, 103, 104, 105, 106, 107});
  row(m.controls, "scene", true, {112, 113, 114, 115, 116, 117, 118, 119});
  add(m.controls, "shift", true, 122);
  row(m.controls, "fader", false, {48, 49, 50, 51, 52, 53, 54, 55});
  add(m.controls, "master", false, 56);
  return m;
}

MidiModel midimix() {
  MidiModel m{"midimix", LedProtocol::MidiMix, {}, 0};
  const int knob_base[8] = {16, 20, 24, 28, 46, 50, 54, 58};
  for (int s = 0; s < 8; ++s)
    for (int k = 0; k < 3; ++k)
      add(m.controls, "knob" + std::to_string(s + 1) + std::string(1, char('a' + k)), false, knob_base[s] + k);
  row(m.controls, "fader", false, {19, 23, 27, 31, 49, 53, 57, 61});
  row(m.controls, "mute", true, {1, 4, 7, 10, 13, 16, 19, 22});
  row(m.controls, "solo", true, {2, 5, 8, 11, 14, 17, 20, 23});
  row(m.controls, "rec", true, {3, 6, 9, 12, 15, 18, 21, 24});
  add(m.controls, "master", false, 62);
  add(m.controls, "bank_left", true, 25);
  add(m.controls, "bank_right", true, 26);
  add(m.controls, "solo_button", true, 27);
  return m;
}

MidiModel launch_control_xl() {
  MidiModel m{"launch_control_xl", LedProtocol::LaunchControlXl, {}, 0};
  const int ch = 8;  // factory template 1
  row(m.controls, "send_a", false, {13, 14, 15, 16, 17, 18, 19, 20}, ch);
  row(m.controls, "send_b", false, {29, 30, 31, 32, 33, 34, 35, 36}, ch);
  row(m.controls, "pan", false, {49, 50, 51, 52, 53, 54, 55, 56}, ch);
  row(m.controls, "fader", false, {77, 78, 79, 80, 81, 82, 83, 84}, ch);
  row(m.controls, "focus", true, {41, 42, 43, 44, 57, 58, 59, 60}, ch);
  row(m.controls, "control", true, {73, 74, 75, 76, 89, 90, 91, 92}, ch);
  for (auto [n, note] : {std::pair{"device", 105}, {"mute", 106}, {"solo", 107}, {"record_arm", 108}}) add(m.controls, n, true, note, ch);
  for (auto [n, cc] : {std::pair{"up", 104}, {"down", 105}, {"left", 106}, {"right", 107}}) add(m.controls, n, false, cc, ch);
  return m;
}

MidiModel xtouch_mini() {
  MidiModel m{"xtouch_mini", LedProtocol::XTouchMini, {}, 8};
  const int ch = 10;  // layer A
  row(m.controls, "encoder", false, {1, 2, 3, 4, 5, 6, 7, 8}, ch);
  row(m.controls, "push", true, {0, 1, 2, 3, 4, 5, 6, 7}, ch);
  row(m.controls, "button", true, {8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23}, ch);
  add(m.controls, "fader", false, 9, ch);
  return m;
}

MidiModel beatstep() {
  MidiModel m{"beatstep", LedProtocol::BeatStep, {}, 0};
  row(m.controls, "encoder", false, {10, 74, 71, 76, 77, 93, 73, 75, 114, 18, 19, 16, 17, 91, 79, 72});
  add(m.controls, "big_knob", false, 7);
  row(m.controls, "pad", true, {44, 45, 46, 47, 48, 49, 50, 51, 36, 37, 38, 39, 40, 41, 42, 43});
  return m;
}

}  // namespace

const MidiModel* midi_model(const std::string& kind) {
  static const MidiModel models[] = {nanokontrol2(), apc_mini_mk2(), midimix(), launch_control_xl(), xtouch_mini(), beatstep()};
  for (const MidiModel& m : models)
    if (kind == m.kind) return &m;
  return nullptr;
}

std::string midi_model_names() { return "nanokontrol2, apc_mini_mk2, midimix, launch_control_xl, xtouch_mini, beatstep"; }

}  // namespace mar
