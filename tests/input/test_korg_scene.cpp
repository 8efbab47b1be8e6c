// The Korg nanoKONTROL2's scene messages (input/korg_scene.h) and its simulator answering them
// as the unit does (firmware_sim/midi_controller.h).
#include "firmware_sim/midi_controller.h"
#include "input/korg_scene.h"
#include "input/usb_midi.h"

#include <gtest/gtest.h>

#include <vector>

namespace mar {
namespace {

std::vector<uint8_t> bytes(std::span<const uint8_t> s) { return {s.begin(), s.end()}; }

TEST(KorgScene, MessagesHaveKorgsBytes) {
  uint8_t out[korg::kSceneMessage];
  EXPECT_EQ(bytes({out, korg::search_request(0x4D, out)}), (std::vector<uint8_t>{0xF0, 0x42, 0x50, 0x00, 0x4D, 0xF7}));
  EXPECT_EQ(bytes({out, korg::dump_request(0, out)}),
            (std::vector<uint8_t>{0xF0, 0x42, 0x40, 0x00, 0x01, 0x13, 0x00, 0x1F, 0x10, 0x00, 0xF7}));
  EXPECT_EQ(bytes({out, korg::write_request(3, 1, out)}),
            (std::vector<uint8_t>{0xF0, 0x42, 0x43, 0x00, 0x01, 0x13, 0x00, 0x1F, 0x11, 0x01, 0xF7}));
  EXPECT_EQ(bytes({out, korg::answer(korg::Kind::Ack, 0, out)}),
            (std::vector<uint8_t>{0xF0, 0x42, 0x40, 0x00, 0x01, 0x13, 0x00, 0x5F, 0x23, 0x00, 0xF7}));
  const size_t n = korg::scene_data(0, korg::factory_scene(), out);
  ASSERT_EQ(n, 402u);  // 13 bytes of head, 339 bytes as 388, F7
  EXPECT_EQ(bytes({out, 13}), (std::vector<uint8_t>{0xF0, 0x42, 0x40, 0x00, 0x01, 0x13, 0x00, 0x7F, 0x7F, 0x02, 0x03, 0x05, 0x40}));
  EXPECT_EQ(out[n - 1], 0xF7);
  for (size_t i = 1; i + 1 < n; ++i) ASSERT_LT(out[i], 0x80) << i;
  // A search reply names the nanoKONTROL2's family (0x13 + 0x01 x 128 = 147).
  const korg::Message r = korg::parse({out, korg::search_reply(5, 0x4D, out)});
  EXPECT_EQ(r.kind, korg::Kind::SearchReply);
  EXPECT_EQ(r.channel, 5);
  EXPECT_EQ(r.echo, 0x4D);
  EXPECT_EQ(r.family, 147);
}

TEST(KorgScene, EightBitBytesTravelSevenAtATimeAndComeBack) {
  korg::Scene s{};
  for (size_t i = 0; i < s.size(); ++i) s[i] = uint8_t(i * 37 + (i % 3 ? 0x80 : 0));  // top bits too
  uint8_t out[korg::kSceneMessage];
  const size_t n = korg::scene_data(2, s, out);
  // The first group: its top-bit byte has bit k set where byte k has bit 7.
  uint8_t top = 0;
  for (int k = 0; k < 7; ++k) top = uint8_t(top | (s[size_t(k)] >> 7) << k);
  EXPECT_EQ(out[13], top);
  EXPECT_EQ(out[14], s[0] & 0x7F);
  korg::Scene back{};
  const korg::Message m = korg::parse({out, n}, &back);
  EXPECT_EQ(m.kind, korg::Kind::SceneData);
  EXPECT_EQ(m.channel, 2);
  EXPECT_EQ(back, s);
}

TEST(KorgScene, WhatIsNotOneOfItsMessagesIsOther) {
  uint8_t out[korg::kSceneMessage];
  const size_t n = korg::scene_data(0, korg::factory_scene(), out);
  std::vector<uint8_t> m(out, out + n);
  EXPECT_EQ(korg::parse(std::vector<uint8_t>(m.begin(), m.end() - 2)).kind, korg::Kind::Other);  // cut short
  m[100] = 0x90;  // a status byte inside
  EXPECT_EQ(korg::parse(m).kind, korg::Kind::Other);
  const uint8_t other_maker[] = {0xF0, 0x00, 0x20, 0x6B, 0x7F, 0x42, 0x02, 0x00, 0x10, 0x70, 0x01, 0xF7};
  EXPECT_EQ(korg::parse(other_maker).kind, korg::Kind::Other);
  const uint8_t other_model[] = {0xF0, 0x42, 0x40, 0x00, 0x01, 0x04, 0x00, 0x1F, 0x10, 0x00, 0xF7};  // a nanoKONTROL (1)
  EXPECT_EQ(korg::parse(other_model).kind, korg::Kind::Other);
  const uint8_t note[] = {0x90, 0x40, 0x7F};
  EXPECT_EQ(korg::parse(note).kind, korg::Kind::Other);
}

/// What a simulator answered, as whole MIDI messages (its replies are USB-MIDI records).
std::vector<std::vector<uint8_t>> answers(MidiControllerSim& sim) {
  std::vector<std::vector<uint8_t>> out;
  UsbMidiDecoder d;
  sim.drain(0, [&](const WireRecord& r) {
    d.feed(r.bytes(), [&](uint8_t, const MidiMessage& m) {
      if (m.is_sysex()) out.emplace_back(m.sysex.begin(), m.sysex.end());
      else out.emplace_back(m.bytes, m.bytes + m.size);
    });
  });
  return out;
}

TEST(KorgScene, TheSimulatedUnitAnswersAsTheUnitDoes) {
  MidiControllerSim sim("nanokontrol2");
  uint8_t out[korg::kSceneMessage];
  ASSERT_TRUE(sim.receive(std::span<const uint8_t>(out, korg::search_request(9, out))));
  auto a = answers(sim);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(korg::parse(a[0]).kind, korg::Kind::SearchReply);
  EXPECT_EQ(korg::parse(a[0]).echo, 9);
  // Its scene: the factory's, the LED mode Internal; the CC lights nothing then.
  ASSERT_TRUE(sim.receive(std::span<const uint8_t>(out, korg::dump_request(0, out))));
  a = answers(sim);
  ASSERT_EQ(a.size(), 1u);
  korg::Scene s{};
  ASSERT_EQ(korg::parse(a[0], &s).kind, korg::Kind::SceneData);
  EXPECT_EQ(s, korg::factory_scene());
  const uint8_t solo1[] = {0xB0, 32, 127};
  EXPECT_FALSE(sim.receive(solo1));
  // A request on another channel than its global one is not for it.
  EXPECT_FALSE(sim.receive(std::span<const uint8_t>(out, korg::dump_request(3, out))));
  EXPECT_TRUE(answers(sim).empty());
  // The scene back with the LED mode External: ACK, and its lights follow CCs; nothing stored.
  s[korg::kLedModeAt] = 1;
  ASSERT_TRUE(sim.receive(std::span<const uint8_t>(out, korg::scene_data(0, s, out))));
  a = answers(sim);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(korg::parse(a[0]).kind, korg::Kind::Ack);
  EXPECT_TRUE(sim.external_leds());
  EXPECT_FALSE(sim.stored_external_leds());
  EXPECT_TRUE(sim.receive(solo1));
  EXPECT_EQ(sim.led("solo1"), 127);
  // A scene it cannot take (an LED mode it has not) is refused and changes nothing.
  s[korg::kLedModeAt] = 7;
  ASSERT_TRUE(sim.receive(std::span<const uint8_t>(out, korg::scene_data(0, s, out))));
  a = answers(sim);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(korg::parse(a[0]).kind, korg::Kind::Nak);
  EXPECT_TRUE(sim.external_leds());
  // Written: stored.
  ASSERT_TRUE(sim.receive(std::span<const uint8_t>(out, korg::write_request(0, 0, out))));
  a = answers(sim);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(korg::parse(a[0]).kind, korg::Kind::WriteDone);
  EXPECT_TRUE(sim.stored_external_leds());
}

}  // namespace
}  // namespace mar
