// LED feedback's own rules (app/loop/leds.h): a light is sent on change, at most once per 20 ms
// (the last state wins), at most 32 a frame; a device that reconnects gets its init messages and
// every light again; an echo of a light within 100 ms is recognised, nothing else is.
#include "app/loop/leds.h"

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
