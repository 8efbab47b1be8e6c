// USB-MIDI event packets: all 69 corpus cases (29 decode, 40 encode), and stream decoding.
#include "input/usb_midi.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

namespace mar {
namespace {

using test::hex_bytes;

TEST(UsbMidi, CorpusPacketVectors) {
  const auto path = test::corpus_dir() / "midi/parser-vectors/usb_midi_packet_vectors.json";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "corpus not found: " << path;
  std::ifstream f(path);
  const auto doc = nlohmann::json::parse(f);
  int cases = 0;
  for (const auto& v : doc["decode"]) {
    SCOPED_TRACE("decode " + v["name"].get<std::string>());
    const auto pk = hex_bytes(v["packet_hex"]);
    ASSERT_EQ(pk.size(), 4u);
    const UsbMidiPacket p = usb_midi_decode(pk.data());
    EXPECT_EQ(p.cable, v["cable"].get<int>());
    EXPECT_EQ(std::vector<uint8_t>(p.payload, p.payload + p.size), hex_bytes(v["payload_hex"]));
    EXPECT_EQ(p.is_sysex, v["is_sysex"].get<bool>());
    EXPECT_EQ(p.sysex_start, v["is_sysex_start"].get<bool>());
    EXPECT_EQ(p.sysex_end, v["is_sysex_end"].get<bool>());
    ++cases;
  }
  for (const auto& v : doc["encode"]) {
    SCOPED_TRACE("encode " + v["name"].get<std::string>());
    const auto payload = hex_bytes(v["payload_hex"]);
    uint8_t pk[4] = {0xAA, 0xAA, 0xAA, 0xAA};
    const auto err = usb_midi_encode(uint8_t(v["cable"].get<int>()), payload, pk);
    if (v.contains("error")) {
      EXPECT_EQ(std::string(usb_midi_error_name(err)), v["error"].get<std::string>());
    } else {
      EXPECT_EQ(err, UsbMidiEncodeError::None);
      EXPECT_EQ(std::vector<uint8_t>(pk, pk + 4), hex_bytes(v["packet_hex"]));
    }
    ++cases;
  }
  EXPECT_EQ(cases, 69);
}

TEST(UsbMidi, StreamAssemblesSysexPerCableAndDropsPartialPackets) {
  // Cable 0: SysEx F0 01 02 03 04 F7 across packets; cable 2 interleaves a CC; then a
  // realtime clock on cable 0 inside the SysEx, and 3 stray bytes at the end.
  const std::vector<uint8_t> in = {0x04, 0xF0, 0x01, 0x02, 0x2B, 0xB0, 0x07, 0x64, 0x0F, 0xF8, 0, 0,
                                   0x06, 0x03, 0xF7, 0x00, 0x00, 0x00, 0x00, 0x00, 0x19, 0x90, 0x3C};
  UsbMidiDecoder d;
  std::vector<std::pair<int, std::vector<uint8_t>>> got;
  d.feed(in, [&](uint8_t cable, const MidiMessage& m) {
    if (m.is_sysex())
      got.push_back({cable, std::vector<uint8_t>(m.sysex.begin(), m.sysex.end())});
    else
      got.push_back({cable, std::vector<uint8_t>(m.bytes, m.bytes + m.size)});
  });
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[0], (std::pair<int, std::vector<uint8_t>>{2, {0xB0, 0x07, 0x64}}));
  EXPECT_EQ(got[1], (std::pair<int, std::vector<uint8_t>>{0, {0xF8}}));
  EXPECT_EQ(got[2], (std::pair<int, std::vector<uint8_t>>{0, {0xF0, 0x01, 0x02, 0x03, 0xF7}}));
  EXPECT_EQ(d.dropped_bytes(), 3u);
}

TEST(UsbMidi, EncodeDecodeRoundTripForEveryChannelMessage) {
  for (int status = 0x80; status < 0xF0; status += 0x10)
    for (int ch = 0; ch < 16; ch += 5)
      for (int cable = 0; cable < 16; cable += 7) {
        const uint8_t msg[3] = {uint8_t(status | ch), 0x12, 0x34};
        uint8_t pk[4];
        ASSERT_EQ(usb_midi_encode(uint8_t(cable), msg, pk), UsbMidiEncodeError::None);
        UsbMidiDecoder d;
        int n = 0;
        d.feed(std::span<const uint8_t>(pk, 4), [&](uint8_t c, const MidiMessage& m) {
          EXPECT_EQ(c, cable);
          EXPECT_EQ(m.bytes[0], msg[0]);
          EXPECT_EQ(m.bytes[1], 0x12);
          ++n;
        });
        EXPECT_EQ(n, 1);
      }
}

}  // namespace
}  // namespace mar
