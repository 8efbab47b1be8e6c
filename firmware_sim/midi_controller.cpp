#include "firmware_sim/midi_controller.h"

#include "input/usb_midi.h"

#include <algorithm>
#include <cmath>

namespace mar {

int MidiControllerSim::cc_of(const std::string& c) {
  auto indexed = [&](const char* prefix, int base) -> int {
    const std::string p = prefix;
    if (c.rfind(p, 0) != 0 || c.size() != p.size() + 1) return -1;
    const int i = c.back() - '1';
    return i >= 0 && i < 8 ? base + i : -1;
  };
  for (auto [p, base] : {std::pair{"fader", 0}, {"knob", 16}, {"solo", 32}, {"mute", 48}, {"rec", 64}})
    if (int cc = indexed(p, base); cc >= 0) return cc;
  static const std::pair<const char*, int> transport[] = {
      {"play", 41}, {"stop", 42}, {"rewind", 43}, {"forward", 44}, {"record", 45}, {"cycle", 46},
      {"marker_set", 60}, {"marker_prev", 61}, {"marker_next", 62}, {"track_prev", 58}, {"track_next", 59}};
  for (auto [name, cc] : transport)
    if (c == name) return cc;
  return -1;
}

void MidiControllerSim::send_cc(int64_t t_ns, int cc, int value) {
  const uint8_t msg[3] = {0xB0, uint8_t(cc & 0x7F), uint8_t(value & 0x7F)};
  uint8_t pk[4];
  usb_midi_encode(0, msg, pk);
  emit(t_ns, pk);
  position_[cc & 0x7F] = value;
}

void MidiControllerSim::move(const std::string& control, double t_s, double to, double dur_s) {
  const int cc = cc_of(control);
  if (cc < 0) return;
  const int from = position_[cc];
  const int target = int(std::lround(std::clamp(to, 0.0, 1.0) * 127));
  if (dur_s <= 0 || from == target) {
    if (from != target || dur_s <= 0) send_cc(to_ns(t_s), cc, target);
    return;
  }
  // The firmware scans its ADC at 1 kHz and sends a CC when the 7-bit value changes. A
  // move sends at most 127 CCs however long it lasts, so the scan jumps from one change to
  // the next: an estimate from where the value passes half-way to the next, then stepped to
  // the exact first scan that rounds differently (a move over a day is 127 steps, not 10^8).
  const int64_t steps = int64_t(std::ceil(dur_s * 1000));
  const double span = target - from;
  auto value_at = [&](int64_t k) { return int(std::lround(from + span * (double(k) / double(steps)))); };
  const int dir = target > from ? 1 : -1;
  int64_t k = 0;
  int last = from;
  while (last != target && !too_many_) {
    const double half = (last + dir * 0.5 - from) / span;
    int64_t next = std::clamp<int64_t>(int64_t(half * double(steps)), k + 1, steps);
    while (next > k + 1 && value_at(next - 1) != last) --next;
    while (value_at(next) == last) ++next;  // ends: value_at(steps) == target
    last = value_at(next);
    send_cc(to_ns(t_s + double(next) / double(steps) * dur_s), cc, last);
    k = next;
  }
}

void MidiControllerSim::send_realtime(int64_t t_ns, uint8_t status) {
  uint8_t pk[4];
  usb_midi_encode(0, std::span<const uint8_t>(&status, 1), pk);
  emit(t_ns, pk);
}

void MidiControllerSim::clock(double t_s, double bpm, double jitter_s, double dur_s, uint32_t seed) {
  const double period = 60.0 / (bpm * 24);
  uint32_t x = seed * 2654435761u + 1;
  send_realtime(to_ns(std::max(0.0, t_s - period / 2)), 0xFA);  // (before the first tick, whatever its jitter)
  const long ticks = long(dur_s / period);
  for (long k = 0; k < ticks; ++k) {
    x = x * 1664525u + 1013904223u;
    const double j = jitter_s * (2.0 * double(x >> 8) / double(1u << 24) - 1.0);
    send_realtime(to_ns(t_s + double(k) * period + j), 0xF8);
  }
  send_realtime(to_ns(t_s + double(ticks) * period), 0xFC);
}

void MidiControllerSim::press(const std::string& control, double t_s, double hold_s) {
  const int cc = cc_of(control);
  if (cc < 0) return;
  send_cc(to_ns(t_s), cc, 127);
  send_cc(to_ns(t_s + std::max(hold_s, 0.001)), cc, 0);
}

Result<bool> MidiControllerSim::action(double t, const std::vector<std::string>& w) {
  using R = Result<bool>;
  // move CONTROL VALUE [over SECONDS] | press CONTROL [for SECONDS] | clock BPM [jitter S] [for S]
  if (w.size() >= 2 && w[0] == "clock") {
    double bpm = 0, jitter = 0, dur = 60;
    if (!parse_number(w[1], bpm) || bpm < 20 || bpm > 300) return R::failure("clock needs a tempo of 20..300 BPM");
    for (size_t i = 2; i < w.size(); i += 2) {
      if (i + 1 >= w.size()) return R::failure("expected 'clock BPM [jitter SECONDS] [for SECONDS]'");
      double v = 0;
      if (!parse_number(w[i + 1], v) || v < 0) return R::failure("'" + w[i] + "' needs a number of seconds");
      if (w[i] == "jitter" && v < 60.0 / (bpm * 24) / 2) jitter = v;
      else if (w[i] == "for" && v <= 100000) dur = v;
      else return R::failure("expected 'clock BPM [jitter SECONDS] [for SECONDS]' (jitter under half a tick)");
    }
    clock(t, bpm, jitter, dur, uint32_t(std::lround(t * 1000)) + 1);  // (the jitter's seed: the line's time)
    return R::success(true);
  }
  if (w.size() < 2) return R::failure("expected 'move CONTROL VALUE [over S]', 'press CONTROL [for S]' or 'clock BPM'");
  if (cc_of(w[1]) < 0)
    return R::failure("unknown control '" + w[1] + "' (fader1-8, knob1-8, solo1-8, mute1-8, rec1-8, play, stop, ...)");
  double dur = 0;
  if (w[0] == "move") {
    double v = 0;
    if (w.size() < 3 || !parse_number(w[2], v) || v < 0 || v > 1) return R::failure("move needs a value in 0..1");
    if (w.size() == 5 && w[3] == "over" && parse_number(w[4], dur) && dur >= 0) {
    } else if (w.size() != 3) {
      return R::failure("expected 'move CONTROL VALUE [over SECONDS]'");
    }
    move(w[1], t, v, dur);
    return R::success(true);
  }
  if (w[0] == "press") {
    dur = 0.1;
    if (w.size() == 4 && w[2] == "for" && parse_number(w[3], dur) && dur >= 0) {
    } else if (w.size() != 2) {
      return R::failure("expected 'press CONTROL [for SECONDS]'");
    }
    press(w[1], t, dur);
    return R::success(true);
  }
  return R::failure("unknown action '" + w[0] + "' (move, press, clock)");
}

}  // namespace mar
