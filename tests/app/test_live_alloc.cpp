// After warm-up a live frame allocates nothing — with every simulated device feeding the
// decoders, mapping with filters, soft takeover and rotation, solving and rendering.
#include "alloc_counter.h"
#include "app/alloc_count.h"
#include "app/live.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace mar {
namespace {

// Loads a show headless at 120 Hz, runs 30 warm-up frames, then 570 frames that must not
// allocate (counted by the test's operator new and by the show itself).
std::unique_ptr<LiveShow> run_steady(const std::string& path) {
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.warmup = 30;
  auto s = LiveShow::load(path, o);
  EXPECT_TRUE(s.ok()) << s.error;
  if (!s.ok()) return nullptr;
  LiveShow& show = **s.value;
  for (int f = 0; f < 30; ++f) show.frame(int64_t(f * 1e9 / 120));
  const long before = test::allocation_count();
  for (int f = 30; f < 600; ++f) show.frame(int64_t(f * 1e9 / 120));
  EXPECT_EQ(test::allocation_count() - before, 0);
  EXPECT_EQ(show.allocations_after_warmup(), 0u);
  return std::move(*s.value);
}

TEST(LiveAlloc, SteadyFramesAllocateNothing) {
  set_allocation_counter(&heap_allocation_count);
  const std::string rig = (test::source_dir() / "config/rigs/figure.toml").string();
  const std::string path = test::write_temp("alloc.toml", "[show]\nrig = \"" + rig + R"("
rate = 120
[display]
width = 200
height = 240
[[device]]
name = "korg"
sim = "nanokontrol2"
script = """
0.0 move fader1 0.0
0.1 move fader1 1 over 1.5
0.2 move knob1 1 over 1.0
1.0 press solo1 for 0.1
loop 2.0
"""
[[device]]
name = "knobs"
sim = "knob_box"
bounce_ms = 2
script = """
0.0 turn 1 10 over 1.0
1.0 turn 1 -10 over 1.0
loop 2.0
"""
[[device]]
name = "pad"
sim = "gamepad"
script = """
0.0 stick left 1,0.5 over 0.8
1.0 stick left -1,-0.5 over 0.8
loop 2.0
"""
[[group]]
name = "head"
handles = ["head"]
pivot_handle = "chest"
[[pose]]
name = "p"
handles = { right-hand = [260.0, 140.0] }
[[binding]]
device = "korg"
control = "cc 0"
target = "handle.left-hand.y"
range = [250.0, 110.0]
filter = { min_cutoff = 1.0, beta = 0.3 }
slew = 400.0
[[binding]]
device = "korg"
control = "cc 16"
target = "rotate.head"
[[binding]]
device = "korg"
control = "cc 32"
target = "pose.p"
[[binding]]
device = "knobs"
control = "encoder 1"
target = "handle.hips.x"
mode = "delta"
step = 1.5
[[binding]]
device = "pad"
control = "usage x"
target = "handle.left-foot.x"
deadzone = 0.1
)");
  const std::unique_ptr<LiveShow> s = run_steady(path);
  ASSERT_TRUE(s);
  LiveShow& show = *s;
  EXPECT_GT(show.mapping().stats().matched, 500u);  // the devices really drove it
}

// Pen grabs and releases (taking over a handle, and a new handle away from the handles:
// a rank-2 update of the factorisation) allocate nothing either, and re-factorise nothing.
TEST(LiveAlloc, PenGrabsAndReleasesAllocateNothing) {
  set_allocation_counter(&heap_allocation_count);
  const std::string rig = (test::source_dir() / "config/rigs/figure.toml").string();
  const std::string path = test::write_temp("grab.toml", "[show]\nrig = \"" + rig + R"("
rate = 120
[display]
width = 200
height = 240
[[device]]
name = "pen"
sim = "pen_tablet"
script = """
0.1 stroke 0.5,0.45 0.62,0.42 0.7,0.5 over 0.4 pressure 0.7
0.7 stroke 0.38,0.8 0.3,0.85 over 0.4 pressure 0.6
loop 1.2
"""
[[binding]]
device = "pen"
control = "pointer"
target = "grab"
)");
  const std::unique_ptr<LiveShow> s = run_steady(path);
  ASSERT_TRUE(s);
  LiveShow& show = *s;
  const auto j = nlohmann::json::parse(show.stats_json());
  EXPECT_GE(j["grabs"]["count"].get<int>(), 16);  // 4 strokes down and up per 1.2 s loop... at least 4 loops
  EXPECT_EQ(j["refactorizations"]["count"], 0);
}

}  // namespace
}  // namespace mar
