#include "firmware_sim/midi_controller.h"
#include "firmware_sim/midi_models.h"

#include "input/usb_midi.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>

namespace mar {

MidiControllerSim::MidiControllerSim(const std::string& kind) : model_(midi_model(kind)) {
  if (!model_) model_ = midi_model("nanokontrol2");
  led_.assign(model_->controls.size() + size_t(model_->rings), -1);
  led_channel_.assign(led_.size(), 0);
}

const char* MidiControllerSim::kind() const { return model_->kind; }
const std::vector<MidiControl>& MidiControllerSim::controls() const { return model_->controls; }

const MidiControl* MidiControllerSim::control(const std::string& name) const {
  for (const MidiControl& c : model_->controls)
    if (c.name == name) return &c;
  return nullptr;
}

int MidiControllerSim::cc_of(const std::string& c) {
  for (const MidiControl& m : midi_model("nanokontrol2")->controls)
    if (m.name == c) return m.number;
  return -1;
}

void MidiControllerSim::send_cc(int64_t t_ns, int cc, int value, int channel) {
  const uint8_t msg[3] = {uint8_t(0xB0 | (channel & 0x0F)), uint8_t(cc & 0x7F), uint8_t(value & 0x7F)};
  uint8_t pk[4];
  usb_midi_encode(0, msg, pk);
  emit(t_ns, pk);
  position_[channel & 0x0F][cc & 0x7F] = value;
}

void MidiControllerSim::send(int64_t t_ns, const MidiControl& c, int value) {
  if (!c.note) {
    send_cc(t_ns, c.number, value, c.channel);
    return;
  }
  const uint8_t msg[3] = {uint8_t((value ? 0x90 : 0x80) | (c.channel & 0x0F)), uint8_t(c.number & 0x7F), uint8_t(value & 0x7F)};
  uint8_t pk[4];
  usb_midi_encode(0, msg, pk);
  emit(t_ns, pk);
}

void MidiControllerSim::move(const std::string& control, double t_s, double to, double dur_s) {
  const MidiControl* m = this->control(control);
  if (!m || m->note) return;
  const int cc = m->number, ch = m->channel;
  const int from = position_[ch][cc];
  const int target = int(std::lround(std::clamp(to, 0.0, 1.0) * 127));
  if (dur_s <= 0 || from == target) {
    if (from != target || dur_s <= 0) send_cc(to_ns(t_s), cc, target, ch);
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
    send_cc(to_ns(t_s + double(next) / double(steps) * dur_s), cc, last, ch);
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

void MidiControllerSim::press(const std::string& control, double t_s, double hold_s, int velocity) {
  const MidiControl* m = this->control(control);
  if (!m) return;
  send(to_ns(t_s), *m, m->note ? std::clamp(velocity, 1, 127) : 127);
  send(to_ns(t_s + std::max(hold_s, 0.001)), *m, 0);
}

void MidiControllerSim::send_message(int64_t t_ns, std::span<const uint8_t> msg) {
  uint8_t pk[4];
  usb_midi_encode(0, msg, pk);
  emit(t_ns, pk);
}

template <class F>
void MidiControllerSim::sweep(double t_s, int from, int to, double dur_s, F emit_value) {
  if (dur_s <= 0 || from == to) {
    emit_value(to_ns(t_s), to);
    return;
  }
  // One message per 7-bit change, each at the time the linear sweep reaches it.
  const int dir = to > from ? 1 : -1;
  for (int v = from + dir;; v += dir) {
    emit_value(to_ns(t_s + dur_s * double(v - from) / double(to - from)), v);
    if (v == to) break;
  }
}

void MidiControllerSim::pressure(const std::string& control, double t_s, double to, double dur_s) {
  const MidiControl* m = this->control(control);
  if (!m || !m->note) return;
  const int ch = m->channel & 0x0F, note = m->number & 0x7F;
  const int target = int(std::lround(std::clamp(to, 0.0, 1.0) * 127));
  sweep(t_s, pressure_[ch][note], target, dur_s, [&](int64_t t, int v) {
    const uint8_t msg[3] = {uint8_t(0xA0 | ch), uint8_t(note), uint8_t(v)};
    send_message(t, msg);
  });
  pressure_[ch][note] = target;
}

void MidiControllerSim::aftertouch(double t_s, double to, double dur_s, int channel) {
  const int ch = channel & 0x0F;
  const int target = int(std::lround(std::clamp(to, 0.0, 1.0) * 127));
  sweep(t_s, aftertouch_[ch], target, dur_s, [&](int64_t t, int v) {
    const uint8_t msg[2] = {uint8_t(0xD0 | ch), uint8_t(v)};
    send_message(t, msg);
  });
  aftertouch_[ch] = target;
}

bool MidiControllerSim::set_led(int index, int value, int channel) {
  if (index < 0 || size_t(index) >= led_.size()) {
    ++ignored_;
    return false;
  }
  led_[size_t(index)] = value;
  led_channel_[size_t(index)] = channel;
  return true;
}

bool MidiControllerSim::receive(std::span<const uint8_t> m) {
  const auto& cs = model_->controls;
  auto find = [&](bool note, int number, int channel) {
    for (size_t i = 0; i < cs.size(); ++i)
      if (cs[i].note == note && cs[i].number == number && cs[i].channel == channel) return int(i);
    return -1;
  };
  auto named = [&](const char* prefix) {  // a control whose name starts so has an LED
    return [&, prefix](int i) { return i >= 0 && cs[size_t(i)].name.rfind(prefix, 0) == 0 ? i : -1; };
  };
  if (m.size() < 3 && !(m.size() >= 1 && m[0] == 0xF0)) {
    ++ignored_;
    return false;
  }
  const int status = m[0] & 0xF0, ch = m[0] & 0x0F;
  const bool note_on = status == 0x90, note_off = status == 0x80, cc = status == 0xB0;
  const int value = note_off ? 0 : m.size() >= 3 ? m[2] : 0;
  switch (model_->leds) {
    case LedProtocol::NanoKontrol2: {  // CCs on channel 1 to the buttons, in External LED mode only
      if (m[0] == 0xF0) return korg(m);
      if (!cc || ch != 0 || !external_leds()) break;
      const int i = find(false, m[1], 0);
      if (i >= 0 && cs[size_t(i)].name.rfind("fader", 0) != 0 && cs[size_t(i)].name.rfind("knob", 0) != 0) return set_led(i, value, ch);
      break;
    }
    case LedProtocol::ApcMiniMk2: {  // note-ons: pads take a colour and a brightness (the channel)
      if (!note_on && !note_off) break;
      const int i = [&] {
        for (size_t k = 0; k < cs.size(); ++k)
          if (cs[k].note && cs[k].number == m[1] && cs[k].name != "shift") return int(k);
        return -1;
      }();
      if (i >= 0) return set_led(i, value, ch);
      break;
    }
    case LedProtocol::MidiMix: {  // mute, rec arm and the bank buttons: note-on 127 lights, 0 does not
      if ((!note_on && !note_off) || ch != 0) break;
      const int i = find(true, m[1], 0);
      for (const char* p : {"mute", "rec", "bank_"})
        if (named(p)(i) >= 0) return set_led(i, value, ch);
      break;
    }
    case LedProtocol::LaunchControlXl: {  // buttons: note-on on the template's channel, velocity a colour
      if ((!note_on && !note_off) || ch != 8) break;
      const int i = find(true, m[1], 8);
      if (i >= 0) return set_led(i, note_off ? 12 : value, ch);
      break;
    }
    case LedProtocol::XTouchMini: {  // the global channel (1): button LEDs by note 0-15, rings CC 9-16
      if (ch != 0) break;
      if ((note_on || note_off) && m[1] < 16) {
        const MidiControl* b = control("button" + std::to_string(m[1] + 1));
        return set_led(int(b - cs.data()), value, ch);
      }
      if (cc && m[1] >= 9 && m[1] <= 16) return set_led(int(cs.size()) + m[1] - 9, value, ch);
      if (cc && ((m[1] >= 1 && m[1] <= 8) || m[1] == 127)) return true;  // ring modes, operation mode
      break;
    }
    case LedProtocol::BeatStep: {  // F0 00 20 6B 7F 42 02 00 10 7p vv F7
      static const uint8_t head[] = {0xF0, 0x00, 0x20, 0x6B, 0x7F, 0x42, 0x02, 0x00, 0x10};
      if (m.size() != 12 || !std::equal(std::begin(head), std::end(head), m.begin()) || (m[9] & 0xF0) != 0x70 || m[11] != 0xF7) break;
      const MidiControl* p = control("pad" + std::to_string((m[9] & 0x0F) + 1));
      return set_led(int(p - cs.data()), m[10], 0);
    }
  }
  ++ignored_;
  return false;
}

bool MidiControllerSim::korg(std::span<const uint8_t> m) {
  // As the unit: a search is answered on any channel, the rest only on its global channel.
  uint8_t out[korg::kSceneMessage];
  korg::Scene in{};
  const korg::Message q = korg::parse(m, &in);
  const int ch = stored_[0] & 0x0F;
  size_t n = 0;
  if (q.kind == korg::Kind::SearchRequest) n = korg::search_reply(ch, q.echo, out);
  else if (q.kind != korg::Kind::Other && q.channel != ch) n = 0;
  else if (q.kind == korg::Kind::DumpRequest) n = korg::scene_data(ch, scene_, out);
  else if (q.kind == korg::Kind::SceneData) {
    const bool ok = in[korg::kLedModeAt] <= 1 && in[1] <= 5;  // (an LED or control mode it has not: NAK)
    if (ok) scene_ = in;
    n = korg::answer(ok ? korg::Kind::Ack : korg::Kind::Nak, ch, out);
  } else if (q.kind == korg::Kind::WriteRequest) {
    stored_ = scene_;
    n = korg::answer(korg::Kind::WriteDone, ch, out);
  }
  if (n == 0) {
    ++ignored_;
    return false;
  }
  return reply_midi(std::span<const uint8_t>(out, n));
}

int MidiControllerSim::led(const std::string& name) const {
  const auto& cs = model_->controls;
  for (size_t i = 0; i < cs.size(); ++i)
    if (cs[i].name == name) return led_[i];
  if (name.rfind("ring", 0) == 0 && name.size() > 4) {
    const int k = std::atoi(name.c_str() + 4) - 1;
    if (k >= 0 && k < model_->rings) return led_[cs.size() + size_t(k)];
  }
  return -1;
}

int MidiControllerSim::led_channel(const std::string& name) const {
  const auto& cs = model_->controls;
  for (size_t i = 0; i < cs.size(); ++i)
    if (cs[i].name == name) return led_channel_[i];
  return -1;
}

std::string MidiControllerSim::leds() const {
  std::string out;
  const auto& cs = model_->controls;
  for (size_t i = 0; i < led_.size(); ++i) {
    if (led_[i] < 0) continue;
    if (!out.empty()) out += ' ';
    out += (i < cs.size() ? cs[i].name : "ring" + std::to_string(i - cs.size() + 1)) + "=" + std::to_string(led_[i]);
  }
  return out;
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
  if (w.size() == 2 && w[0] == "ledmode" && model_->leds == LedProtocol::NanoKontrol2) {  // the stored scene's
    if (w[1] != "external" && w[1] != "internal") return R::failure("expected 'ledmode external' or 'ledmode internal'");
    stored_[korg::kLedModeAt] = scene_[korg::kLedModeAt] = w[1] == "external";
    return R::success(true);
  }
  if (w[0] == "aftertouch") {  // the channel's pressure: aftertouch VALUE [over S]
    double v = 0, over = 0;
    if (w.size() < 2 || !parse_number(w[1], v) || v < 0 || v > 1 ||
        !(w.size() == 2 || (w.size() == 4 && w[2] == "over" && parse_number(w[3], over) && over >= 0)))
      return R::failure("expected 'aftertouch VALUE [over SECONDS]' (VALUE 0..1)");
    aftertouch(t, v, over);
    return R::success(true);
  }
  if (w.size() < 2)
    return R::failure("expected 'move CONTROL VALUE [over S]', 'press CONTROL [for S] [velocity V]', "
                      "'pressure CONTROL VALUE [over S]', 'aftertouch VALUE [over S]' or 'clock BPM'");
  const MidiControl* c = control(w[1]);
  if (!c) {
    std::string names;
    for (size_t i = 0; i < model_->controls.size() && i < 6; ++i) names += (i ? ", " : "") + model_->controls[i].name;
    return R::failure("unknown control '" + w[1] + "' (" + names + ", ...)");
  }
  double dur = 0;
  if (w[0] == "move") {
    double v = 0;
    if (w.size() < 3 || !parse_number(w[2], v) || v < 0 || v > 1) return R::failure("move needs a value in 0..1");
    if (c->note) return R::failure("'" + w[1] + "' is a button: press it");
    if (w.size() == 5 && w[3] == "over" && parse_number(w[4], dur) && dur >= 0) {
    } else if (w.size() != 3) {
      return R::failure("expected 'move CONTROL VALUE [over SECONDS]'");
    }
    move(w[1], t, v, dur);
    return R::success(true);
  }
  if (w[0] == "press") {  // press CONTROL [for SECONDS] [velocity 1..127]
    dur = 0.1;
    double velocity = 127;
    size_t i = 2;
    if (i + 1 < w.size() && w[i] == "for") {
      if (!parse_number(w[i + 1], dur) || dur < 0) return R::failure("press: 'for' needs seconds >= 0");
      i += 2;
    }
    if (i + 1 < w.size() && w[i] == "velocity") {
      if (!parse_number(w[i + 1], velocity) || velocity < 1 || velocity > 127 || velocity != std::floor(velocity))
        return R::failure("press: velocity must be a whole number 1..127");
      if (!c->note) return R::failure("'" + w[1] + "' sends a CC: only a pad or key has a velocity");
      i += 2;
    }
    if (i != w.size()) return R::failure("expected 'press CONTROL [for SECONDS] [velocity 1..127]'");
    press(w[1], t, dur, int(velocity));
    return R::success(true);
  }
  if (w[0] == "pressure") {  // a pad's own pressure: pressure CONTROL VALUE [over SECONDS]
    double v = 0;
    if (!c->note) return R::failure("'" + w[1] + "' sends a CC: only a pad or key has a pressure");
    if (w.size() < 3 || !parse_number(w[2], v) || v < 0 || v > 1 ||
        !(w.size() == 3 || (w.size() == 5 && w[3] == "over" && parse_number(w[4], dur) && dur >= 0)))
      return R::failure("expected 'pressure CONTROL VALUE [over SECONDS]' (VALUE 0..1)");
    pressure(w[1], t, v, dur);
    return R::success(true);
  }
  return R::failure("unknown action '" + w[0] + "' (move, press, pressure, aftertouch, clock)");
}

}  // namespace mar
