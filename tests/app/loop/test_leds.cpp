// LED feedback's own rules (app/loop/leds.h): a light is sent on change, at most once per 20 ms
// (the last state wins), at most 32 a frame; a device that reconnects gets its init messages and
// every light again; an echo of a light within 100 ms is recognised, nothing else is.
#include "app/loop/leds.h"
#include "firmware_sim/midi_controller.h"
#include "input/usb_midi.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <vector>

namespace mar {
namespace {

struct Recorder : LedSink {
  std::vector<std::vector<uint8_t>> sent;
  bool send(uint16_t, std::span<const uint8_t> m) override {
    sent.emplace_back(m.begin(), m.end());
    return true;
  }
};

// A device with `n` lit buttons (notes 0..n-1, note-on 127) toggling triggers 0..n-1.
struct Lights {
  ShowConfig show;
  Mapping m;
  explicit Lights(int n) {
    ShowDevice d;
    d.name = "mix";
    d.init = {{0xB0, 0x7F, 0x00}};
    for (int i = 0; i < n; ++i) {
      DeviceLed l;
      l.name = "b" + std::to_string(i);
      l.control = "note " + std::to_string(i);
      l.bytes = {0x90, uint8_t(i), 0};
      l.value_at = 2;
      d.leds.push_back(l);
    }
    show.devices.push_back(d);
    m.set_handles({"h"}, {Vec2(0, 0)});
    m.set_swaps({}, {}, size_t(n));
    for (int i = 0; i < n; ++i) {
      Binding b;
      b.control.kind = ControlSpec::Note;
      b.control.number = uint32_t(i);
      b.control.text = "note " + std::to_string(i);
      b.target = TargetKind::Trigger;
      b.index = i;
      m.add_binding(b);
    }
  }
};

constexpr int64_t kMs = 1'000'000;

TEST(LedFeedback, AChangeIsSentAtMostEvery20msAndTheLastStateWins) {
  Lights s(1);
  LedFeedback f;
  f.prepare(s.show, s.m);
  Recorder out;
  std::vector<char> on(1, 0);
  const DeviceState connected[] = {DeviceState::Connected};
  f.frame(0, s.m, {}, on, connected, out);
  ASSERT_EQ(out.sent.size(), 2u);  // the init message, then the light (dark)
  EXPECT_EQ(out.sent[0], (std::vector<uint8_t>{0xB0, 0x7F, 0x00}));
  EXPECT_EQ(out.sent[1], (std::vector<uint8_t>{0x90, 0x00, 0x00}));
  for (int t = 1; t < 20; ++t) {  // toggling every millisecond: nothing until 20 ms have passed
    on[0] = char(t % 2);
    f.frame(t * kMs, s.m, {}, on, connected, out);
  }
  EXPECT_EQ(out.sent.size(), 2u);
  on[0] = 1;
  f.frame(20 * kMs, s.m, {}, on, connected, out);
  ASSERT_EQ(out.sent.size(), 3u);
  EXPECT_EQ(out.sent[2], (std::vector<uint8_t>{0x90, 0x00, 0x7F}));
  f.frame(21 * kMs, s.m, {}, on, connected, out);  // unchanged: nothing
  EXPECT_EQ(out.sent.size(), 3u);
}

TEST(LedFeedback, AtMost32AFrameAndTheRestTheNext) {
  Lights s(40);
  LedFeedback f;
  f.prepare(s.show, s.m);
  Recorder out;
  std::vector<char> on(40, 1);
  const DeviceState connected[] = {DeviceState::Connected};
  f.frame(0, s.m, {}, on, connected, out);
  EXPECT_EQ(out.sent.size(), 1u + 32);
  f.frame(kMs, s.m, {}, on, connected, out);
  EXPECT_EQ(out.sent.size(), 1u + 40);
}

TEST(LedFeedback, AReconnectedDeviceGetsItsInitAndEveryLightAgain) {
  Lights s(3);
  LedFeedback f;
  f.prepare(s.show, s.m);
  Recorder out;
  std::vector<char> on = {1, 0, 1};
  DeviceState st[] = {DeviceState::Connected};
  f.frame(0, s.m, {}, on, st, out);
  EXPECT_EQ(out.sent.size(), 4u);
  st[0] = DeviceState::Unplugged;
  f.frame(100 * kMs, s.m, {}, on, st, out);
  EXPECT_EQ(out.sent.size(), 4u);  // nothing to a device that is gone
  st[0] = DeviceState::Connected;
  f.frame(200 * kMs, s.m, {}, on, st, out);
  ASSERT_EQ(out.sent.size(), 8u);
  EXPECT_EQ(out.sent[4], (std::vector<uint8_t>{0xB0, 0x7F, 0x00}));
}

TEST(LedFeedback, OnlyAnEchoOfALightWithin100msIsAnEcho) {
  Lights s(2);
  LedFeedback f;
  f.prepare(s.show, s.m);
  Recorder out;
  std::vector<char> on = {1, 0};
  const DeviceState connected[] = {DeviceState::Connected};
  f.frame(0, s.m, {}, on, connected, out);
  auto note = [](ControlKind k, int n, int v) {
    Event e;
    e.kind = k;
    e.number = uint32_t(n);
    e.value = v;
    return e;
  };
  EXPECT_TRUE(f.echo(note(ControlKind::MidiNoteOn, 0, 127), 50 * kMs));   // what was sent, back
  EXPECT_TRUE(f.echo(note(ControlKind::MidiNoteOff, 1, 0), 50 * kMs));    // a dark light comes back as a note-off
  EXPECT_FALSE(f.echo(note(ControlKind::MidiNoteOn, 0, 100), 50 * kMs));  // another velocity: a press
  EXPECT_FALSE(f.echo(note(ControlKind::MidiNoteOn, 0, 127), 150 * kMs)); // too late: a press
  EXPECT_FALSE(f.echo(note(ControlKind::MidiCC, 0, 127), 50 * kMs));
  EXPECT_EQ(f.echoes(), 2u);
  nlohmann::json j;
  f.add_stats(j);
  EXPECT_EQ(j["leds"]["echoes_dropped"], 2);
  EXPECT_EQ(j["leds"]["lights"], 2);
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

// A sink wired to a simulated nanoKONTROL2 (or to nothing that answers): what the frame sends
// reaches the simulator, and its answers come back as the decoder's last SysEx would.
struct KorgUnit : LedSink {
  MidiControllerSim sim{"nanokontrol2"};
  bool answers = true;
  UsbMidiDecoder dec;
  std::vector<uint8_t> last;
  uint64_t count = 0;
  int led_messages = 0;
  bool send(uint16_t, std::span<const uint8_t> m) override {
    if (m[0] != 0xF0) ++led_messages;
    if (answers) sim.receive(m);
    return true;
  }
  std::span<const uint8_t> last_sysex(uint16_t, uint64_t& n) override {
    sim.drain(0, [&](const WireRecord& r) {
      dec.feed(r.bytes(), [&](uint8_t, const MidiMessage& m) {
        if (!m.is_sysex()) return;
        last.assign(m.sysex.begin(), m.sysex.end());
        ++count;
      });
    });
    n = count;
    return last;
  }
};

Lights korg_lights() {
  Lights s(2);
  s.show.devices[0].init.clear();
  s.show.devices[0].korg_external_leds = true;
  return s;
}

TEST(LedFeedback, ANanoKontrol2IsPutInExternalLedModeBeforeItsLightsAndAgainOnReconnecting) {
  Lights s = korg_lights();
  LedFeedback f;
  f.prepare(s.show, s.m);
  KorgUnit unit;
  std::vector<char> on{1, 0};
  std::vector<DeviceState> state{DeviceState::Connected};
  uint16_t dev = 9;
  const char* news = nullptr;
  int64_t t = 0;
  auto frame = [&] {
    f.frame(t, s.m, {}, on, state, unit);
    t += 8 * kMs;
  };
  frame();  // search device
  EXPECT_EQ(unit.led_messages, 0);
  frame();  // its reply: the dump request
  frame();  // its scene: sent back with the LED mode External
  EXPECT_TRUE(unit.sim.external_leds());
  EXPECT_EQ(unit.led_messages, 0) << "no light before the unit has said it took the scene";
  frame();  // ACK: the lights
  EXPECT_FALSE(unit.sim.stored_external_leds()) << "nothing written to the unit's memory";
  EXPECT_EQ(unit.led_messages, 2);
  EXPECT_EQ(unit.sim.led("b0"), -1);  // (the test's lights are notes; the unit's are CCs)
  ASSERT_TRUE(f.take_news(dev, news));
  EXPECT_EQ(dev, 0);
  EXPECT_NE(std::string(news).find("External"), std::string::npos) << news;
  EXPECT_FALSE(f.take_news(dev, news)) << "said once";
  nlohmann::json j;
  f.add_stats(j);
  EXPECT_EQ(j["leds"]["korg_led_mode"], "switched");
  // Unplugged (its scene is the stored one again) and back: set up again, then every light.
  state[0] = DeviceState::Unplugged;
  frame();
  unit.sim = MidiControllerSim("nanokontrol2");
  state[0] = DeviceState::Connected;
  for (int i = 0; i < 4; ++i) frame();
  EXPECT_TRUE(unit.sim.external_leds());
  EXPECT_EQ(unit.led_messages, 4);
  // A unit whose scene says External already is only read.
  Lights s2 = korg_lights();
  LedFeedback g;
  g.prepare(s2.show, s2.m);
  KorgUnit set;
  ASSERT_TRUE(set.sim.load_script("0 ledmode external").ok());
  t = 0;
  for (int i = 0; i < 3; ++i, t += 8 * kMs) g.frame(t, s2.m, {}, on, state, set);
  EXPECT_EQ(set.led_messages, 2);
  ASSERT_TRUE(g.take_news(dev, news));
  EXPECT_NE(std::string(news).find("already"), std::string::npos) << news;
}

TEST(LedFeedback, ANanoKontrol2ThatDoesNotAnswerIsSaidAndItsLightsAreSentAnyway) {
  Lights s = korg_lights();
  LedFeedback f;
  f.prepare(s.show, s.m);
  KorgUnit unit;
  unit.answers = false;
  std::vector<char> on{1, 0};
  std::vector<DeviceState> state{DeviceState::Connected};
  uint16_t dev = 0;
  const char* news = nullptr;
  int64_t t = 0;
  for (; t < 990 * kMs; t += 10 * kMs) f.frame(t, s.m, {}, on, state, unit);
  EXPECT_EQ(unit.led_messages, 0) << "waiting for its answer, up to a second";
  EXPECT_FALSE(f.take_news(dev, news));
  for (; t < 1030 * kMs; t += 10 * kMs) f.frame(t, s.m, {}, on, state, unit);
  EXPECT_EQ(unit.led_messages, 2);
  ASSERT_TRUE(f.take_news(dev, news));
  EXPECT_NE(std::string(news).find("Korg Kontrol Editor"), std::string::npos) << news;
  nlohmann::json j;
  f.add_stats(j);
  EXPECT_EQ(j["leds"]["korg_led_mode"], "no answer");
}

}  // namespace
}  // namespace mar
