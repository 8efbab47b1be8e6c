#include "app/loop/recording.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <fstream>

namespace mar {
namespace {

constexpr uint64_t kShow = 0x1234;
const auto kNone = [](uint16_t, std::span<const uint8_t>) {};

TEST(Recording, WhatIsWrittenIsReadBackFrameByFrame) {
  const auto path = (test::temp_dir("recording") / "a.rec").string();
  const uint8_t cc[] = {0x0B, 0xB0, 7, 100};
  const uint8_t desc[] = {1, 1};
  {
    auto r = Recorder::open(path, kShow);
    ASSERT_TRUE(r.ok()) << r.error;
    Recorder& rec = **r.value;
    rec.device(2, desc);
    rec.wire(WireRecord::make(5, WireKind::UsbMidi, cc, 2));
    rec.frame(16666667, 8);
    rec.frame(33333333, 7);  // a frame with no input
    EXPECT_TRUE(rec.flush()) << rec.error();
  }
  auto p = Playback::open(path);
  ASSERT_TRUE(p.ok()) << p.error;
  EXPECT_EQ((*p.value)->identity(), kShow);
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
  EXPECT_EQ((*p.value)->damage(), "");
}

// A hostile recording cannot make a frame hold more than its limit in memory: a frame of
// 70,000 records (no frame marker) is damage, read up to the limit and no further.
TEST(Recording, AFrameOverTheRecordLimitIsDamageNotMemory) {
  const auto path = (test::temp_dir("recording") / "long.rec").string();
  const uint8_t cc[] = {0x0B, 0xB0, 7, 100};
  {
    auto r = Recorder::open(path, kShow);
    ASSERT_TRUE(r.ok()) << r.error;
    for (int k = 0; k < 70000; ++k) (*r.value)->wire(WireRecord::make(k, WireKind::UsbMidi, cc, 0));
    (*r.value)->frame(1, 8);
  }
  auto p = Playback::open(path);
  ASSERT_TRUE(p.ok()) << p.error;
  std::vector<WireRecord> wires;
  int64_t t = 0;
  int it = 0;
  EXPECT_FALSE((*p.value)->next_frame(wires, t, it, kNone));
  EXPECT_EQ(wires.size(), Playback::kMaxFrameRecords);
  EXPECT_NE((*p.value)->damage().find("more than 65,536 records"), std::string::npos) << (*p.value)->damage();
}

// A take of 200 frames, three devices' worth of records a frame.
std::string write_take(const std::string& path, int frames = 200, int iterations = 8) {
  auto r = Recorder::open(path, kShow);
  EXPECT_TRUE(r.ok()) << r.error;
  const uint8_t cc[] = {0x0B, 0xB0, 7, 100};
  for (int f = 0; f < frames; ++f) {
    for (int k = 0; k < 3; ++k) (*r.value)->wire(WireRecord::make(f * 10 + k, WireKind::UsbMidi, cc, 0));
    (*r.value)->frame(f, iterations);
  }
  return path;
}

long frames_played(Playback& p) {
  std::vector<WireRecord> wires;
  int64_t t = 0;
  int it = 0;
  long n = 0;
  while (p.next_frame(wires, t, it, kNone)) ++n;
  return n;
}

// A cut take plays to its last whole block (at most 64 frames are lost) and says where it was
// cut; a bit flipped anywhere after the header is found by its block's checksum.
TEST(Recording, ACutOrFlippedTakeIsFoundAndSaid) {
  const auto dir = test::temp_dir("recording-bad");
  const std::string path = write_take((dir / "cut.rec").string());
  const auto size = std::filesystem::file_size(path);
  std::filesystem::copy_file(path, dir / "flip.rec");
  std::filesystem::resize_file(path, size - 6);  // cut inside the last block
  {
    auto p = Playback::open(path);
    ASSERT_TRUE(p.ok()) << p.error;
    const long n = frames_played(**p.value);
    EXPECT_GE(n, 200 - 64);
    EXPECT_LT(n, 200);
    EXPECT_NE((*p.value)->damage().find("cut short"), std::string::npos) << (*p.value)->damage();
    EXPECT_NE((*p.value)->damage().find("played to frame " + std::to_string(n)), std::string::npos) << (*p.value)->damage();
  }
  // Every byte after the header, one bit each: never a silent different take.
  std::string bytes;
  {
    std::ifstream in(dir / "flip.rec", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  int found = 0, tried = 0;
  for (size_t at = 20; at < bytes.size(); at += 37, ++tried) {
    std::string b = bytes;
    b[at] = char(b[at] ^ (1 << (at % 8)));
    const auto flipped = (dir / "f.rec").string();
    std::ofstream(flipped, std::ios::binary) << b;
    auto p = Playback::open(flipped);
    ASSERT_TRUE(p.ok()) << p.error;
    const long n = frames_played(**p.value);
    if (!(*p.value)->damage().empty() && n < 200) ++found;
  }
  EXPECT_EQ(found, tried);
  // The header too.
  std::string b = bytes;
  b[10] = char(b[10] ^ 4);
  std::ofstream(dir / "h.rec", std::ios::binary) << b;
  auto h = Playback::open((dir / "h.rec").string());
  ASSERT_FALSE(h.ok());
  EXPECT_NE(h.error.find("damaged header"), std::string::npos) << h.error;
}

// A frame asking for more solver iterations than any show may (65,535 would take 200 ms a
// frame) is damage, not a slow frame.
TEST(Recording, IterationsNoShowMayAskForAreDamage) {
  const auto dir = test::temp_dir("recording-it");
  for (int it : {0, Playback::kMaxIterations + 1, 65535}) {
    auto p = Playback::open(write_take((dir / ("it" + std::to_string(it) + ".rec")).string(), 3, it));
    ASSERT_TRUE(p.ok()) << p.error;
    EXPECT_EQ(frames_played(**p.value), 0) << it;
    EXPECT_NE((*p.value)->damage().find("solver iterations"), std::string::npos) << (*p.value)->damage();
  }
  auto ok = Playback::open(write_take((dir / "ok.rec").string(), 3, Playback::kMaxIterations));
  ASSERT_TRUE(ok.ok());
  EXPECT_EQ(frames_played(**ok.value), 3);
}

// An empty device description is a description (found by fuzz_recording: its empty buffer went
// to memcpy as a null pointer).
TEST(Recording, AnEmptyDeviceDescriptionPlays) {
  const auto path = (test::temp_dir("recording-empty") / "e.rec").string();
  {
    auto r = Recorder::open(path, kShow);
    ASSERT_TRUE(r.ok()) << r.error;
    (*r.value)->device(0, {});
    (*r.value)->frame(1, 8);
  }
  auto p = Playback::open(path);
  ASSERT_TRUE(p.ok()) << p.error;
  size_t described = 99;
  std::vector<WireRecord> wires;
  int64_t t = 0;
  int it = 0;
  EXPECT_TRUE((*p.value)->next_frame(wires, t, it, [&](uint16_t, std::span<const uint8_t> d) { described = d.size(); }));
  EXPECT_EQ(described, 0u);
}

TEST(Recording, OtherFilesAreRefused) {
  const auto dir = test::temp_dir("recording-other");
  std::ofstream(dir / "old.rec") << "MARREC02 and more";
  auto old = Playback::open((dir / "old.rec").string());
  ASSERT_FALSE(old.ok());
  EXPECT_NE(old.error.find("older marionette"), std::string::npos) << old.error;
  std::ofstream(dir / "text.rec") << "hello";
  EXPECT_FALSE(Playback::open((dir / "text.rec").string()).ok());
  EXPECT_FALSE(Recorder::open((dir / "no" / "such" / "dir.rec").string(), kShow).ok());
}

// A full disk is said, not hidden: the recorder's writes are checked (/dev/full fails every
// write with ENOSPC).
TEST(Recording, AFullDiskIsSaid) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  auto r = Recorder::open("/dev/full", kShow);
  if (r.ok()) {  // the header may sit in the stdio buffer; the first block fails then
    const uint8_t cc[] = {0x0B, 0xB0, 7, 100};
    for (int f = 0; f < 100; ++f) {
      (*r.value)->wire(WireRecord::make(f, WireKind::UsbMidi, cc, 0));
      (*r.value)->frame(f, 8);
    }
    EXPECT_FALSE((*r.value)->flush());
    EXPECT_NE((*r.value)->error().find("/dev/full: No space left on device"), std::string::npos) << (*r.value)->error();
  } else {
    EXPECT_NE(r.error.find("No space left"), std::string::npos) << r.error;
  }
}

TEST(Recording, Crc32IsTheStandardOne) {
  const std::string s = "123456789";
  EXPECT_EQ(crc32(std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(s.data()), s.size())), 0xCBF43926u);
}

}  // namespace
}  // namespace mar
