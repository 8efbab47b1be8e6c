#include "app/loop/recording.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <fstream>

namespace mar {
namespace {

TEST(Recording, WhatIsWrittenIsReadBackFrameByFrame) {
  const auto path = (test::temp_dir("recording") / "a.rec").string();
  const uint8_t cc[] = {0x0B, 0xB0, 7, 100};
  const uint8_t desc[] = {1, 1};
  {
    auto r = Recorder::open(path);
    ASSERT_TRUE(r.ok()) << r.error;
    Recorder& rec = **r.value;
    rec.device(2, desc);
    rec.wire(WireRecord::make(5, WireKind::UsbMidi, cc, 2));
    rec.frame(16666667, 8);
    rec.frame(33333333, 7);  // a frame with no input
  }
  auto p = Playback::open(path);
  ASSERT_TRUE(p.ok()) << p.error;
  std::vector<WireRecord> wires;
  int64_t t = 0;
  int it = 0;
  std::vector<std::pair<uint16_t, std::vector<uint8_t>>> devices;
  auto on_device = [&](uint16_t s, std::span<const uint8_t> d) { devices.push_back({s, {d.begin(), d.end()}}); };
  ASSERT_TRUE((*p.value)->next_frame(wires, t, it, on_device));
  EXPECT_EQ(t, 16666667);
  EXPECT_EQ(it, 8);
  ASSERT_EQ(devices.size(), 1u);
  EXPECT_EQ(devices[0].first, 2);
  EXPECT_EQ(devices[0].second, std::vector<uint8_t>(desc, desc + 2));
  ASSERT_EQ(wires.size(), 1u);
  EXPECT_EQ(wires[0].source, 2);
  EXPECT_EQ(wires[0].t_ns, 5);
  EXPECT_EQ(wires[0].kind, WireKind::UsbMidi);
  EXPECT_EQ(std::vector<uint8_t>(wires[0].data, wires[0].data + wires[0].size), std::vector<uint8_t>(cc, cc + 4));
  ASSERT_TRUE((*p.value)->next_frame(wires, t, it, on_device));
  EXPECT_TRUE(wires.empty());
  EXPECT_EQ(it, 7);
  EXPECT_FALSE((*p.value)->next_frame(wires, t, it, on_device));
}

// A hostile recording cannot make a frame hold more than its limit in memory: a frame of
// 70,000 records (no frame marker) is damage, read up to the limit and no further.
TEST(Recording, AFrameOverTheRecordLimitIsDamageNotMemory) {
  const auto path = (test::temp_dir("recording") / "long.rec").string();
  const uint8_t cc[] = {0x0B, 0xB0, 7, 100};
  {
    auto r = Recorder::open(path);
    ASSERT_TRUE(r.ok()) << r.error;
    for (int k = 0; k < 70000; ++k) (*r.value)->wire(WireRecord::make(k, WireKind::UsbMidi, cc, 0));
    (*r.value)->frame(1, 8);
  }
  auto p = Playback::open(path);
  ASSERT_TRUE(p.ok()) << p.error;
  std::vector<WireRecord> wires;
  int64_t t = 0;
  int it = 0;
  EXPECT_FALSE((*p.value)->next_frame(wires, t, it, [](uint16_t, std::span<const uint8_t>) {}));
  EXPECT_EQ(wires.size(), Playback::kMaxFrameRecords);
}

TEST(Recording, ATruncatedRecordingStopsCleanlyAndOtherFilesAreRefused) {
  const auto dir = test::temp_dir("recording-bad");
  const auto path = (dir / "cut.rec").string();
  {
    auto r = Recorder::open(path);
    ASSERT_TRUE(r.ok());
    const uint8_t cc[] = {0x0B, 0xB0, 7, 100};
    (*r.value)->frame(1, 8);
    (*r.value)->wire(WireRecord::make(5, WireKind::UsbMidi, cc, 0));
    (*r.value)->frame(2, 8);
  }
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 6);  // cut inside the last records
  auto p = Playback::open(path);
  ASSERT_TRUE(p.ok());
  std::vector<WireRecord> wires;
  int64_t t = 0;
  int it = 0;
  auto none = [](uint16_t, std::span<const uint8_t>) {};
  EXPECT_TRUE((*p.value)->next_frame(wires, t, it, none));
  EXPECT_FALSE((*p.value)->next_frame(wires, t, it, none));
  std::ofstream(dir / "old.rec") << "MARREC01 and more";
  auto old = Playback::open((dir / "old.rec").string());
  ASSERT_FALSE(old.ok());
  EXPECT_NE(old.error.find("older marionette"), std::string::npos) << old.error;
  std::ofstream(dir / "text.rec") << "hello";
  EXPECT_FALSE(Playback::open((dir / "text.rec").string()).ok());
  EXPECT_FALSE(Recorder::open((dir / "no" / "such" / "dir.rec").string()).ok());
}

}  // namespace
}  // namespace mar
