// Random controller streams through the live show: a recording of garbage and of valid
// messages at the most a frame takes (4,000 records a frame), on every device a show has,
// replayed through the whole frame (decoders, mapping, key poses, swaps, attract, solver,
// render). Nothing crashes (this runs under ASan+UBSan too), every handle target and every
// deformed point stays finite, garbage is counted as malformed, and the show keeps mapping.
#include "app/live.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <random>

namespace mar {
namespace {

struct Stream {
  uint64_t malformed = 0, mapped = 0;
  long frames = 0;
  bool finite = true;
};

// Records a take of `frames` frames of random input for every device of `show`.
std::string random_take(const std::string& show, int frames, int per_frame, uint32_t seed) {
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto live = LiveShow::load(show, o);
  EXPECT_TRUE(live.ok()) << live.error;
  if (!live.ok()) return "";
  DeviceSet& set = *(*live.value)->devices();
  const std::string path = (test::temp_dir("random") / ("take" + std::to_string(seed) + ".marrec")).string();
  auto rec = Recorder::open(path, (*live.value)->identity());
  EXPECT_TRUE(rec.ok()) << rec.error;
  Recorder& r = **rec.value;
  std::vector<WireKind> kinds;
  for (size_t i = 0; i < set.size(); ++i) {
    const auto d = set.description(i);
    r.device(uint16_t(i), d);
    auto cfg = DecoderConfig::parse(d);
    kinds.push_back(cfg.ok() ? cfg.value->kind : WireKind::UsbMidi);
  }
  std::mt19937 rng(seed);
  auto byte = [&] { return uint8_t(rng() & 0xFF); };
  for (int f = 0; f < frames; ++f) {
    const int64_t t = int64_t(f) * 16'666'667;
    for (int k = 0; k < per_frame; ++k) {
      const uint16_t src = uint16_t(rng() % kinds.size());
      WireRecord w;
      w.t_ns = t + k;
      w.source = src;
      w.kind = kinds[src];
      const uint32_t pick = rng() % 8;
      if (pick == 0) w.kind = WireKind(1 + rng() % 8);  // a record of another kind (or an unknown one)
      if (pick <= 3) {                                   // garbage of any length
        w.size = uint8_t(rng() % (WireRecord::kMax + 1));
        for (int b = 0; b < w.size; ++b) w.data[b] = byte();
      } else if (w.kind == WireKind::UsbMidi) {          // valid CCs, notes and SysEx pieces at full rate
        w.size = 4 * (1 + rng() % 8);
        for (int b = 0; b < w.size; b += 4) {
          const uint8_t cin = uint8_t(rng() % 4 == 0 ? 0x4 + rng() % 4 : 0xB);
          w.data[b] = cin;
          w.data[b + 1] = uint8_t(cin == 0xB ? 0xB0 | (rng() % 2) : byte());
          w.data[b + 2] = uint8_t(rng() % 72);
          w.data[b + 3] = uint8_t(rng() % 128);
        }
      } else {                                           // the right size, random contents
        w.size = uint8_t(w.kind == WireKind::GpioEdge ? 2 : w.kind == WireKind::EvdevEvent ? 8 : 1 + rng() % 16);
        for (int b = 0; b < w.size; ++b) w.data[b] = byte();
        if (w.kind == WireKind::GpioEdge) w.data[1] &= 1;
      }
      r.wire(w);
    }
    r.frame(t, 8);
  }
  r.flush();
  return path;
}

Stream replay(const std::string& show, const std::string& take) {
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.replay_path = take;
  auto live = LiveShow::load(show, o);
  EXPECT_TRUE(live.ok()) << live.error;
  Stream s;
  if (!live.ok()) return s;
  LiveShow& l = **live.value;
  EXPECT_EQ(l.run(), 0);
  s.frames = l.frames();
  for (const Vec2& t : l.targets()) s.finite = s.finite && std::isfinite(t.x()) && std::isfinite(t.y());
  for (const Points& shape : l.puppet().shapes)
    for (const Vec2& p : shape) s.finite = s.finite && std::isfinite(p.x()) && std::isfinite(p.y());
  const auto j = nlohmann::json::parse(l.stats_json());
  for (const auto& d : j["devices"]) s.malformed += d["malformed"].get<uint64_t>();
  s.mapped = j["events"]["mapped"].get<uint64_t>();
  return s;
}

TEST(LiveRandom, GarbageAndFullRateStreamsOnEveryDeviceKeepTheShowRunning) {
  for (const char* name : {"tests/data/shows/every_sim_looping.toml", "tests/data/shows/pen_grab_looping.toml",
                           "tests/data/shows/attract.toml"}) {
    SCOPED_TRACE(name);
    const std::string show = (test::source_dir() / name).string();
    const int frames = 120, per_frame = 4000;
    const std::string take = random_take(show, frames, per_frame, 11);
    ASSERT_FALSE(take.empty());
    const Stream s = replay(show, take);
    EXPECT_EQ(s.frames, frames);
    EXPECT_TRUE(s.finite);
    EXPECT_GT(s.malformed, uint64_t(frames));  // garbage is seen and counted
    EXPECT_GT(s.mapped, uint64_t(frames));     // and valid messages still drive the show
  }
}

}  // namespace
}  // namespace mar
